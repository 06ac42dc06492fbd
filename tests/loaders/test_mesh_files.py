"""PLY and STL through trimesh: vertices exactly as written, closed meshes wound outwards, broken
files a SceneLoadError; and a big mesh loads, builds its BVH and renders."""

from __future__ import annotations

import time

import numpy as np
import pytest
import trimesh

from wgputrace import Diffuse, Renderer, SceneLoadError, SceneLoadWarning, load_scene, make_icosphere

SPHERE = make_icosphere((0.5, 0.25, -1.0), (0, 0, 0), 1.0, 2, Diffuse("unused"))
FORMATS = {"binary.ply": {"encoding": "binary"}, "ascii.ply": {"encoding": "ascii"}, "binary.stl": {}, "ascii.stl": {}}
# A big mesh for CI (the 1,000,000-triangle case is `bench.big_mesh`'s): 2 x 160 x 160 triangles.
GRID_CELLS = 160
BIG_MESH_SECONDS = 60.0  # load + BVH build + one tiny render; ~3 s here, a hang or a quadratic step fails


def exported(path, triangles: np.ndarray, **options):
    mesh = trimesh.Trimesh(triangles.reshape(-1, 3), np.arange(triangles.size // 3).reshape(-1, 3), process=False)
    file_type = "stl_ascii" if path.name == "ascii.stl" else path.suffix[1:]
    data = mesh.export(file_type=file_type, **options)
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    return path


@pytest.mark.parametrize("name", FORMATS)
def test_vertices_are_read_exactly_and_inward_triangles_turned(tmp_path, name):
    triangles = np.array(SPHERE.vertices)
    triangles[:7] = triangles[:7, [0, 2, 1]]  # seven triangles wound inwards
    with pytest.warns(SceneLoadWarning, match="closed but 7 of its 320 triangles were wound inwards"):
        scene = load_scene(exported(tmp_path / name, triangles, **FORMATS[name]))
    (shape,) = scene.shapes
    if name.startswith("ascii"):  # trimesh writes ASCII files with 8 significant digits
        np.testing.assert_allclose(shape.vertices, SPHERE.vertices, rtol=1e-7, atol=1e-7)
    else:
        np.testing.assert_array_equal(shape.vertices, SPHERE.vertices)
    assert isinstance(shape.material, Diffuse) and shape.material.color == (0.8, 0.8, 0.8)


@pytest.mark.parametrize(
    "name, data, message",
    [
        ("empty.ply", b"", "trimesh cannot read it"),
        (
            "header.ply",
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n",
            "trimesh cannot read it",
        ),
        ("noise.ply", bytes(range(256)) * 3, "trimesh cannot read it"),
        (
            "points.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n",
            "holds no triangles",
        ),
        ("empty.stl", b"solid x\nendsolid x\n", "holds no triangles"),
    ],
)
def test_broken_files_are_named(tmp_path, name, data, message):
    (tmp_path / name).write_bytes(data)
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(tmp_path / name)
    assert caught.value.path == tmp_path / name


def grid_mesh(cells: int) -> np.ndarray:
    """A wavy height field of 2 cells^2 triangles over [-1, 1]^2 in the xz plane, facing +y."""
    x, z = np.meshgrid(np.linspace(-1, 1, cells + 1), np.linspace(-1, 1, cells + 1), indexing="ij")
    y = 0.1 * np.sin(7 * x) * np.cos(5 * z)
    points = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    a = (i * (cells + 1) + j).ravel()
    b, c, d = a + 1, a + cells + 1, a + cells + 2
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([b, d, c], 1)])
    return points[faces].astype(np.float32)


def test_a_big_mesh_loads_builds_and_renders(tmp_path, gpu_context):
    triangles = grid_mesh(GRID_CELLS)
    path = exported(tmp_path / "grid.ply", triangles, encoding="binary")
    start = time.perf_counter()
    scene = load_scene(path)
    renderer = Renderer(scene, 16, 16, seed=1)
    renderer.render(1)
    image = renderer.image()
    assert time.perf_counter() - start < BIG_MESH_SECONDS
    assert renderer.triangle_count == 2 * GRID_CELLS**2
    assert np.all(np.isfinite(image)) and renderer.nonfinite_samples == 0
