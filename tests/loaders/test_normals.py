"""Per-vertex normals read from files: OBJ `vn` through v//n and v/t/n faces, glTF NORMAL under a
node transform; faces without them shade flat, and a normal without direction is an error."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import SceneLoadError, load_scene
from wgputrace.testing.gltf_files import gltf_document, write_glb

# A quad split in two, in z = 0, wound towards +z; its normals lean outwards like a dome's.
QUAD_OBJ = """v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vn -1 -1 2
vn 1 -1 2
vn 1 1 2
vn 0 0 3
o dome
f 1//1 2//2 3//3
f 1/1/1 3/1/3 -1/1/-1
"""


def test_obj_normals_reach_the_corners_normalised(tmp_path):
    path = tmp_path / "dome.obj"
    path.write_text(QUAD_OBJ)
    (shape,) = load_scene(path).shapes
    listed = np.array([[-1, -1, 2], [1, -1, 2], [1, 1, 2], [0, 0, 3]], float)
    listed /= np.linalg.norm(listed, axis=1, keepdims=True)
    np.testing.assert_allclose(shape.normals, listed[[[0, 1, 2], [0, 2, 3]]], rtol=1e-6)
    np.testing.assert_allclose(shape.world_normals, shape.normals)


def test_obj_faces_without_normals_take_their_flat_normal(tmp_path):
    path = tmp_path / "mixed.obj"
    path.write_text(QUAD_OBJ.replace("f 1//1 2//2 3//3", "f 1 2 3"))
    (shape,) = load_scene(path).shapes
    np.testing.assert_allclose(shape.normals[0], [[0, 0, 1]] * 3)
    path.write_text(QUAD_OBJ.replace("f 1//1 2//2 3//3", "f 1 2 3").replace("f 1/1/1 3/1/3 -1/1/-1", "f 1 3 4"))
    assert load_scene(path).shapes[0].normals is None


def test_obj_normals_follow_a_triangle_turned_outwards(tmp_path):
    # a tetrahedron with one face wound inwards: the loader turns it, its normals turn with it
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n" + "".join(f"vn {k} 0 1\n" for k in range(1, 5))
    text += "f 1//1 2//2 3//3\nf 1//1 2//2 4//4\nf 1//1 4//4 3//3\nf 2//2 4//4 3//3\n"
    path = tmp_path / "tetra.obj"
    path.write_text(text)
    with pytest.warns(UserWarning, match="wound inwards"):
        (shape,) = load_scene(path).shapes
    # each corner keeps its own normal: vn k has x = k for vertex k
    corner_of = {tuple(np.array(v, float)): i for i, v in enumerate([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])}
    for triangle, normals in zip(shape.vertices, shape.normals, strict=True):
        for corner, normal in zip(triangle, normals, strict=True):
            expected = np.array([corner_of[tuple(corner.astype(float))] + 1, 0, 1], float)
            np.testing.assert_allclose(normal, expected / np.linalg.norm(expected), rtol=1e-6)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("vn 0 0 3", "vn 0 0 0"), r"dome.obj:9: a normal must have a direction, got vn 0 0 0"),
        (("vn 0 0 3", "vn 0 0 nan"), r"dome.obj:9: .*must be finite"),
        (("3//3", "3//7"), r"dome.obj:11: face normal index 7 is out of range: 4 normals \(vn\)"),
        (("3//3", "3//x"), r"dome.obj:11: face vertex '3//x' has a normal reference that is no index"),
    ],
)
def test_obj_normal_errors_name_the_line(tmp_path, change, message):
    path = tmp_path / "dome.obj"
    path.write_text(QUAD_OBJ.replace(*change))
    with pytest.raises(SceneLoadError, match=message):
        load_scene(path)


def _with_normals(document: dict, blob: bytes, normals: np.ndarray) -> tuple[dict, bytes]:
    data = np.ascontiguousarray(normals, "<f4").tobytes()
    document["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
    document["accessors"].append(
        {"bufferView": len(document["bufferViews"]) - 1, "componentType": 5126, "count": len(normals), "type": "VEC3"}
    )
    document["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = len(document["accessors"]) - 1
    document["buffers"][0]["byteLength"] = len(blob) + len(data)
    return document, blob + data


def test_gltf_normal_round_trip_under_the_node_transform(tmp_path):
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    normals = np.array([[-1, -1, 2], [1, -1, 2], [1, 1, 2], [0, 0, 1]], np.float32)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    document, blob = gltf_document([(positions, faces, None)])
    document, blob = _with_normals(document, blob, normals)
    document["nodes"][0]["scale"] = [2.0, 1.0, 1.0]  # normals take the inverse transpose
    (shape,) = load_scene(write_glb(tmp_path / "quad.glb", document, blob)).shapes
    np.testing.assert_allclose(shape.normals, normals[faces], rtol=1e-6)
    world = normals[faces] * [0.5, 1.0, 1.0]
    np.testing.assert_allclose(shape.world_normals, world / np.linalg.norm(world, axis=-1, keepdims=True), rtol=1e-6)
    # without NORMAL the primitive shades flat
    plain, plain_blob = gltf_document([(positions, faces, None)])
    assert load_scene(write_glb(tmp_path / "flat.glb", plain, plain_blob)).shapes[0].normals is None


def test_gltf_zero_normal_is_an_error_naming_the_primitive(tmp_path):
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    document, blob = gltf_document([(positions, np.array([[0, 1, 2]]), None)])
    document, blob = _with_normals(document, blob, np.array([[0, 0, 1], [0, 0, 0], [0, 0, 1]], np.float32))
    with pytest.raises(SceneLoadError, match=r"primitives\[0\].*triangle 0 has a NaN, infinite or zero-length normal"):
        load_scene(write_glb(tmp_path / "zero.glb", document, blob))
