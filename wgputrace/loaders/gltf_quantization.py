"""Vertex attributes as glTF stores them, core types and KHR_mesh_quantization's integers
(gltfpack's default output) alike, read as float32.

The extension lets POSITION, NORMAL, TANGENT and TEXCOORD_n be 8- or 16-bit integers: normalized
ones map to [-1, 1] (signed, max(c / (2^(b-1) - 1), -1)) or [0, 1] (unsigned, c / (2^b - 1)),
others are taken as they are; the scale and offset that undo the quantisation live in the node's
transform (positions) and KHR_texture_transform (texture coordinates), which the loader applies
anyway. The integer types are accepted whether or not the file lists the extension.
"""

from __future__ import annotations

import numpy as np

QUANTIZATION_EXTENSION = "KHR_mesh_quantization"
BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT, FLOAT = 5120, 5121, 5122, 5123, 5126
# attribute -> (its componentTypes, those that must be normalized, its element type)
VERTEX_ATTRIBUTES = {
    "POSITION": ((FLOAT, BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT), (), "VEC3"),
    "NORMAL": ((FLOAT, BYTE, SHORT), (BYTE, SHORT), "VEC3"),
    "TANGENT": ((FLOAT, BYTE, SHORT), (BYTE, SHORT), "VEC4"),
    "TEXCOORD_0": ((FLOAT, BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT), (), "VEC2"),
}


def vertex_attribute(reader, index, where: str, semantic: str) -> np.ndarray:
    """Accessor `index`, holding `semantic`, as (count, k) float32 values. `reader` is the glTF
    reader (its `item`, `accessor` and `fail`); `where` the JSON path that names the accessor."""
    types, normalized_types, shape = VERTEX_ATTRIBUTES[semantic]
    values = reader.accessor(index, where, types, (shape,))
    if values.dtype.kind == "f":
        return values.astype(np.float32, copy=False)
    entry = reader.item("accessors", index, where)
    normalized = entry.get("normalized", False) is True
    component = entry["componentType"]
    if component in normalized_types and not normalized:
        raise reader.fail(
            f"{where} -> accessors[{index}]", f"{semantic} of componentType {component} must be normalized"
        )
    if not normalized:
        return values.astype(np.float32)
    scaled = values / np.float32(np.iinfo(values.dtype).max)
    return np.maximum(scaled, -1.0).astype(np.float32)  # a signed minimum (-128) is -1 too
