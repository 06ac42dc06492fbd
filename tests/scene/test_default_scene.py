"""The default scene, built by our shape generators, equals the shared OBJ of listing 16."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import default_scene

# The OBJ stores float32 values printed to 9 digits; our generators compute in float64.
VERTEX_TOLERANCE = 1e-5


def read_obj(path):
    """Minimal OBJ reader for the shared file: vertices, faces, and the material of each face."""
    vertices, triangles, materials, current = [], [], [], None
    for line in path.read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append([float(p) for p in parts[1:4]])
        elif parts[0] == "usemtl":
            current = parts[1]
        elif parts[0] == "f":
            triangles.append([int(p.split("/")[0]) - 1 for p in parts[1:4]])
            materials.append(current)
    return np.asarray(vertices)[np.asarray(triangles)], materials


def canonical(triangles: np.ndarray) -> np.ndarray:
    """Each triangle's corners in a fixed order, so a triangle equals itself whatever its winding."""
    order = np.lexsort(triangles.transpose(2, 0, 1)[::-1], axis=-1)
    return np.take_along_axis(triangles, order[..., None], axis=1)


@pytest.fixture(scope="module")
def shared_obj(data_dir):
    return read_obj(data_dir / "cornell_trac0r.obj")


def test_triangles_equal_shared_obj(shared_obj):
    expected, expected_materials = shared_obj
    arrays = default_scene().arrays()
    assert arrays.vertices.shape == expected.shape == (676, 3, 3)
    np.testing.assert_allclose(
        canonical(arrays.vertices.astype(np.float64)), canonical(expected), atol=VERTEX_TOLERANCE
    )
    names = [arrays.materials[i].name for i in arrays.material_index]
    assert names == expected_materials


def test_corner_order_matches_except_fixed_box_winding(shared_obj):
    """Same corners in the same order, except the three box triangles whose winding trac0r had
    inwards: there two corners swap, which flips the normal outwards."""
    expected, _ = shared_obj
    vertices = default_scene().arrays().vertices
    same = np.all(np.abs(vertices - expected) < VERTEX_TOLERANCE, axis=(1, 2))
    assert np.count_nonzero(~same) == 6  # 3 triangles in each of the two boxes


def test_material_indices_not_copies():
    arrays = default_scene().arrays()
    assert arrays.material_index.dtype == np.uint32
    assert len(arrays.materials) == 6
    assert sorted(m.name for m in arrays.materials) == ["emissive", "glass", "glossy", "green", "red", "white"]


def test_camera_matches_shared_conventions(data_dir):
    data = np.load(data_dir / "cornell_trac0r.npz")
    camera = default_scene().camera
    right, up, forward = camera.basis()
    np.testing.assert_allclose(camera.position, data["camera_position"], atol=1e-6)
    np.testing.assert_allclose(forward, data["camera_forward"], atol=1e-6)
    np.testing.assert_allclose(right, data["camera_right"], atol=1e-6)
    assert camera.vfov_degrees == pytest.approx(float(data["camera_vfov_deg"]), abs=1e-4)


def test_materials_match_shared_table(data_dir):
    data = np.load(data_dir / "cornell_trac0r.npz")
    materials = {m.name: m for m in default_scene().materials}
    for index, name in enumerate(data["material_names"]):
        material = materials[str(name)]
        assert int(material.kind) == int(data["material_type"][index])
        np.testing.assert_allclose(material.color, data["material_color"][index], rtol=1e-6)
    assert materials["glass"].ior == pytest.approx(float(data["material_ior"][4]), rel=1e-6)
    assert materials["glossy"].roughness == pytest.approx(0.09)
    assert materials["emissive"].emittance == 15.0
