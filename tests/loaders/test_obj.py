"""OBJ and MTL: the shared Cornell box loads as the default scene bit for bit, the documented
material mapping holds row by row, and every malformed line is an error naming file and line."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from wgputrace import (
    Diffuse,
    Emitter,
    Glass,
    Glossy,
    SceneLoadError,
    SceneLoadWarning,
    default_scene,
    load_scene,
    render,
)
from wgputrace.loaders.framing import FRAMING_VFOV_DEGREES
from wgputrace.render.scene_records import material_records
from wgputrace.scene import DegenerateTrianglesWarning

SIZE = 24
SEED = 11
SPP = 2


def write(directory: Path, name: str, text: str) -> Path:
    path = directory / name
    path.write_text(text)
    return path


def test_shared_cornell_obj_is_the_default_scene(gpu_context, data_dir):
    with pytest.warns(SceneLoadWarning) as caught:
        loaded = load_scene(data_dir / "cornell_trac0r.obj")
    assert [str(w.message).split(": ", 1)[1] for w in caught] == [
        f"shape '{box}' is closed but 3 of its 12 triangles were wound inwards; turned them outwards "
        "(Glass needs the inside behind the normal)"
        for box in ("box1", "box2")
    ]  # trac0r's box winding, which our generator fixes the same way (swapping corners 1 and 2)
    expected = default_scene()
    assert [s.name for s in loaded.shapes] == [s.name for s in expected.shapes]
    a, b = loaded.arrays(), expected.arrays()
    np.testing.assert_array_equal(a.vertices, b.vertices)  # float32 values and corner order
    np.testing.assert_array_equal(a.material_index, b.material_index)
    assert [type(m) for m in a.materials] == [type(m) for m in b.materials]
    assert material_records(a.materials).tobytes() == material_records(b.materials).tobytes()
    lamp = next(m for m in a.materials if isinstance(m, Emitter))
    np.testing.assert_allclose(lamp.radiance, (15, 13.95, 12.75), rtol=1e-15)
    # an OBJ has no camera: put the default scene's in, and the pictures are the same
    loaded.camera = expected.camera
    np.testing.assert_array_equal(
        render(loaded, SPP, SIZE, SIZE, seed=SEED), render(expected, SPP, SIZE, SIZE, seed=SEED)
    )


MTL_TABLE = """
newmtl lamp
Kd 0.5 0.5 0.5
Ke 4 2 1
newmtl clear
Kd 0 0 0
Tf 0.9 0.8 0.7
Ni 1.33
d 0.5
newmtl window
illum 7
newmtl gold
Kd 0.2 0.2 0.2
Ks 1 0.8 0.3
Pm 1
Pr 0.25
newmtl phong
Kd 0 0 0
Ks 0.9 0.9 0.9
Ns 98
newmtl metal_from_kd
Kd 0.6 0.5 0.4
Pm 0.75
newmtl plastic
Kd 0.3 0.4 0.5
Ks 0.5 0.5 0.5
newmtl bare
"""


def test_mtl_mapping_follows_the_documented_table(tmp_path):
    write(tmp_path, "table.mtl", MTL_TABLE)
    names = ["lamp", "clear", "window", "gold", "phong", "metal_from_kd", "plastic", "bare"]
    lines = ["mtllib table.mtl", "v 0 0 0", "v 1 0 0", "v 0 1 0"]
    for name in names:
        lines += [f"o {name}", f"usemtl {name}", "f 1 2 3"]
    scene = load_scene(write(tmp_path, "table.obj", "\n".join(lines)))
    m = {shape.name: shape.material for shape in scene.shapes}
    assert isinstance(m["lamp"], Emitter) and m["lamp"].color == (1.0, 0.5, 0.25) and m["lamp"].emittance == 4.0
    assert isinstance(m["clear"], Glass) and (m["clear"].color, m["clear"].ior) == ((0.9, 0.8, 0.7), 1.33)
    assert isinstance(m["window"], Glass) and (m["window"].color, m["window"].ior) == ((1.0, 1.0, 1.0), 1.5)
    assert isinstance(m["gold"], Glossy) and (m["gold"].color, m["gold"].roughness) == ((1.0, 0.8, 0.3), 0.25)
    assert isinstance(m["phong"], Glossy) and m["phong"].roughness == pytest.approx(math.sqrt(2 / 100))
    assert isinstance(m["metal_from_kd"], Glossy) and m["metal_from_kd"].color == (0.6, 0.5, 0.4)
    assert isinstance(m["plastic"], Diffuse) and m["plastic"].color == (0.3, 0.4, 0.5)
    assert isinstance(m["bare"], Diffuse) and m["bare"].color == (0.8, 0.8, 0.8)


def test_polygons_negative_indices_references_and_names(tmp_path):
    text = """
    # a quad as a fan, referenced with texture and normal indices, then a triangle counting back
    v 0 0 0
    v 1 0 0
    v 1 1 0
    v 0 1 0
    vt 0 0
    vn 0 0 1
    o quad
    f 1/1/1 2/1/1 3//1 4
    g back
    f -1 -2 -3  # a comment after a statement
    o quad
    f 1 3 4
    """
    scene = load_scene(write(tmp_path, "shapes.obj", text))
    assert [(s.name, s.triangle_count) for s in scene.shapes] == [("quad", 2), ("back", 1), ("quad#2", 1)]
    np.testing.assert_array_equal(scene.shapes[0].vertices[1], [[0, 0, 0], [1, 1, 0], [0, 1, 0]])
    np.testing.assert_array_equal(scene.shapes[1].vertices[0], [[0, 1, 0], [1, 1, 0], [1, 0, 0]])


VERTICES = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"


@pytest.mark.parametrize(
    "obj, mtl, file, line, message",
    [
        ("v 1 2\n", None, "bad.obj", 1, "a vertex needs 3 coordinates, got 'v 1 2'"),
        ("v 1 nan 3\n", None, "bad.obj", 1, "vertex coordinates must be finite, got '1 nan 3'"),
        ("v 1 x 3\n", None, "bad.obj", 1, "vertex coordinates must be numbers"),
        (VERTICES + "f 1 2\n", None, "bad.obj", 4, "a face needs at least 3 vertices"),
        (VERTICES + "f 1 2 9\n", None, "bad.obj", 4, "face vertex index 9 is out of range: 3 vertices"),
        (VERTICES + "f 0 1 2\n", None, "bad.obj", 4, "face vertex index 0 is out of range"),
        (VERTICES + "f -4 1 2\n", None, "bad.obj", 4, "face vertex index -4 is out of range"),
        (VERTICES + "f a b c\n", None, "bad.obj", 4, "face vertex 'a' does not start with an index"),
        ("v 1e39 0 0\n" + VERTICES + "f 1 2 3\n", None, "bad.obj", 1, "beyond float32's range"),
        (VERTICES + "mtllib m.mtl\nusemtl x\nf 1 2 3\n", "newmtl x\nd 0.5\nNi 0\n", "m.mtl", 3, r"ior must be in \(0"),
        (VERTICES + "mtllib m.mtl\n", "newmtl x\n\nKd 0.5 -1 0.5\n", "m.mtl", 3, "color must be finite and >= 0"),
        (VERTICES + "mtllib m.mtl\n", "newmtl x\nKd 1.5 1 1\n", "m.mtl", 2, "must be <= 1"),
        (VERTICES + "mtllib m.mtl\n", "newmtl x\nKd 0 0 0\nKs 1 1 1\nNs -5\n", "m.mtl", 4, "Ns .* must be >= 0"),
        (VERTICES + "mtllib m.mtl\n", "newmtl x\nKs 1 1 1\nPm 1\nPr nan\n", "m.mtl", 4, "Pr must be finite"),
        (VERTICES + "mtllib m.mtl\n", "newmtl x\nKe 1 2\n", "m.mtl", 2, "Ke takes 1 or 3 numbers, got 2"),
        (VERTICES + "mtllib m.mtl\n", "Kd 1 1 1\n", "m.mtl", 1, "Kd before any newmtl"),
        (VERTICES, None, "bad.obj", None, "holds no triangles"),
        (VERTICES + "f 1 1 2\n", None, "bad.obj", None, "all 1 triangles have zero area"),
    ],
)
def test_errors_name_file_line_and_problem(tmp_path, obj, mtl, file, line, message):
    if mtl is not None:
        write(tmp_path, "m.mtl", mtl)
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(write(tmp_path, "bad.obj", obj))
    assert caught.value.path == tmp_path / file and caught.value.line == line
    assert str(caught.value).startswith(f"{tmp_path / file}:{line}: " if line else f"{tmp_path / file}: ")


def test_missing_mtllib_and_unknown_material_warn_and_fall_back_to_grey(tmp_path):
    obj = write(tmp_path, "m.obj", VERTICES + "mtllib nowhere.mtl\nusemtl brass\nf 1 2 3\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = load_scene(obj)
    messages = [str(w.message) for w in caught if issubclass(w.category, SceneLoadWarning)]
    assert any(f"{obj}:4: mtllib file {tmp_path / 'nowhere.mtl'} not found" in m for m in messages)
    assert any(f"{obj}:5: usemtl 'brass' names no material" in m for m in messages)
    assert isinstance(scene.shapes[0].material, Diffuse) and scene.shapes[0].material.color == (0.8, 0.8, 0.8)


def test_files_without_a_camera_are_framed_by_the_documented_rule(tmp_path):
    text = "v -1 0 2\nv 3 0 2\nv -1 2 4\nf 1 2 3\n"
    scene = load_scene(write(tmp_path, "frame.obj", text))
    centre, radius = np.array([1.0, 1.0, 3.0]), np.linalg.norm([4.0, 2.0, 2.0]) / 2
    distance = radius / math.sin(math.radians(FRAMING_VFOV_DEGREES / 2))
    np.testing.assert_allclose(scene.camera.position, centre - [0, 0, distance], rtol=1e-12)
    assert scene.camera.forward == (0.0, 0.0, 1.0) and scene.camera.vfov_degrees == FRAMING_VFOV_DEGREES


def test_zero_area_triangles_load_and_are_dropped_with_a_count_when_rendered(tmp_path, gpu_context):
    text = VERTICES + "v 2 0 0\nf 1 2 3\nf 1 2 4\nf 2 2 3\n"
    scene = load_scene(write(tmp_path, "slivers.obj", text))
    assert scene.triangle_count == 3
    with pytest.warns(DegenerateTrianglesWarning, match="dropped 2 zero-area triangles; the first is triangle 1"):
        image = render(scene, 1, 8, 8)
    assert np.all(np.isfinite(image))
