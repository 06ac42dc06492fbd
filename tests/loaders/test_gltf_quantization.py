"""KHR_mesh_quantization (gltfpack's default): integer POSITION, NORMAL, TANGENT and TEXCOORD_0
load as floats, normalized ones scaled to [-1, 1] or [0, 1]; quantised normals compressed with
meshopt's OCTAHEDRAL filter, as gltfpack writes them, load to the box's normals."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import SceneLoadError, load_scene
from wgputrace.loaders.gltf import _Reader
from wgputrace.loaders.gltf_quantization import vertex_attribute
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, MATERIALS, add_view, gltf_document, write_glb
from wgputrace.testing.meshopt_files import meshopt_glb

BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT = 5120, 5121, 5122, 5123
POSITION_BITS = 14  # gltfpack's default: positions as integers below 2^14, scaled back by the node
NORMAL_BITS = 8


def box_normals() -> np.ndarray:
    corners = BOX[BOX_INDICES]
    faces = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return np.repeat(faces / np.linalg.norm(faces, axis=1, keepdims=True), 3, axis=0)


def quantized_box(path, normals_stride: int = 4, normalized: bool = True, compressed: bool = False):
    """The unit box as gltfpack stores it: uint16 positions (rows of 8 bytes) scaled by the node,
    int8 normalized normals (rows of `normals_stride` bytes), optionally compressed with meshopt."""
    scale = 2.0 ** -(POSITION_BITS - 1)  # the box spans [-1, 1]: integer steps of `scale`
    positions = np.zeros((len(BOX), 4), "<u2")
    positions[:, :3] = np.round((BOX + 1) / scale)
    normals = np.zeros((len(BOX), normals_stride), "<i1")
    normals[:, :3] = np.round(box_normals() * 127)
    document, blob = gltf_document([], materials=MATERIALS[:1])
    accessors = []
    for rows, component, extra in (
        (positions, UNSIGNED_SHORT, {}),
        (normals, BYTE, {"normalized": normalized}),
        (BOX_INDICES.astype("<u4").reshape(-1, 1), 5125, {}),
    ):
        view, blob = add_view(document, blob, rows.tobytes())
        if rows.shape[1] != 1:
            document["bufferViews"][view]["byteStride"] = rows.itemsize * rows.shape[1]
        kind = "VEC3" if rows.shape[1] > 1 else "SCALAR"
        accessors.append({"bufferView": view, "componentType": component, "count": len(rows), "type": kind, **extra})
    primitive = {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}
    document.update(
        accessors=accessors,
        meshes=[{"primitives": [primitive]}],
        nodes=[{"mesh": 0, "scale": [scale] * 3, "translation": [-1.0] * 3}],
        scenes=[{"nodes": [0]}],
        extensionsUsed=["KHR_mesh_quantization"],
        extensionsRequired=["KHR_mesh_quantization"],
    )
    if not compressed:
        return write_glb(path, document, blob)
    meshopt = pytest.importorskip("meshopt")
    directions = np.zeros((len(BOX), 4), np.float32)
    directions[:, :3] = box_normals()
    encoded = meshopt.encode_filter_oct(directions, normals_stride, NORMAL_BITS)
    return meshopt_glb(path, document, blob, filtered={1: ("OCTAHEDRAL", encoded)})


def test_quantized_positions_and_normals_load_within_their_steps(tmp_path):
    (shape,) = load_scene(quantized_box(tmp_path / "box.glb")).shapes
    np.testing.assert_allclose(shape.world_vertices.reshape(-1, 3), BOX[BOX_INDICES].reshape(-1, 3), atol=1e-6)
    np.testing.assert_allclose(shape.normals.reshape(-1, 3), box_normals()[BOX_INDICES.ravel()], atol=0.5 / 127)


def test_octahedral_compressed_normals_load_as_gltfpack_writes_them(tmp_path):
    (shape,) = load_scene(quantized_box(tmp_path / "box.glb", compressed=True)).shapes
    np.testing.assert_allclose(shape.normals.reshape(-1, 3), box_normals()[BOX_INDICES.ravel()], atol=1.5 / 127)


def test_an_integer_normal_must_be_normalized(tmp_path):
    path = quantized_box(tmp_path / "box.glb", normalized=False)
    with pytest.raises(SceneLoadError, match=r"attributes.NORMAL -> accessors\[1\]: NORMAL of componentType 5120 must"):
        load_scene(path)


@pytest.mark.parametrize(
    "component, stored, expected",
    [
        (BYTE, [-128, -127, 0, 127], [-1, -1, 0, 1]),
        (UNSIGNED_BYTE, [0, 255, 51, 0], [0, 1, 0.2, 0]),
        (SHORT, [-32768, 32767, 0, 16384], [-1, 1, 0, 16384 / 32767]),
        (UNSIGNED_SHORT, [0, 65535, 13107, 0], [0, 1, 0.2, 0]),
    ],
)
def test_normalized_texture_coordinates_scale_by_their_type(tmp_path, component, stored, expected):
    document, blob = gltf_document([(BOX, BOX_INDICES, 0)])
    dtype = {BYTE: "<i1", UNSIGNED_BYTE: "<u1", SHORT: "<i2", UNSIGNED_SHORT: "<u2"}[component]
    view, blob = add_view(document, blob, np.array(stored, dtype).tobytes())
    document["accessors"].append(
        {"bufferView": view, "componentType": component, "count": 2, "type": "VEC2", "normalized": True}
    )
    reader = _Reader(write_glb(tmp_path / "uv.glb", document, blob))
    values = vertex_attribute(reader, 2, "TEXCOORD_0", "TEXCOORD_0")
    np.testing.assert_allclose(values.ravel(), expected, rtol=1e-6)
