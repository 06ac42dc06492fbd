"""glTF vertex colours: a primitive's COLOR_0, which multiplies its material's base colour (and
alpha) as the glTF 2.0 specification says; the colour attributes after it are named in one warning
per file and not read.

| COLOR_0 accessor | read as |
|---|---|
| FLOAT VEC3 / VEC4 | linear RGB(A) as written, each in [0, 1] |
| normalized UNSIGNED_BYTE / UNSIGNED_SHORT VEC3 / VEC4 | value / 255 or / 65535 |
| VEC3 | alpha 1 |

Any other type (SCALAR, VEC2, signed or non-normalized integers) and values outside [0, 1] are a
SceneLoadError naming the attribute's JSON path.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from .errors import SceneLoadWarning

if TYPE_CHECKING:
    from .gltf import _Reader

COLOR_ATTRIBUTE = "COLOR_0"
# FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT: the componentTypes glTF allows for COLOR_n
COLOR_COMPONENT_TYPES = (5126, 5121, 5123)
COLOR_ELEMENT_TYPES = ("VEC3", "VEC4")


def vertex_colors(
    reader: _Reader, attributes: dict, faces: np.ndarray, vertex_count: int, where: str
) -> np.ndarray | None:
    """(n, 3, 4) float32 linear RGBA of COLOR_0 at the corners of `faces` (primitive `where`), or
    None where the primitive has none."""
    if COLOR_ATTRIBUTE not in attributes:
        return None
    index = reader.get(attributes, COLOR_ATTRIBUTE, int, f"{where}.attributes")
    where = f"{where}.attributes.{COLOR_ATTRIBUTE}"
    values = reader.accessor(index, where, COLOR_COMPONENT_TYPES, COLOR_ELEMENT_TYPES)
    if values.dtype.kind == "u":
        entry = reader.item("accessors", index, where)
        if not reader.get(entry, "normalized", bool, f"{where} -> accessors[{index}]", False):
            raise reader.fail(
                f"{where} -> accessors[{index}]",
                f"{values.dtype.name} colours must be normalized (glTF reads them as value / max)",
            )
        values = values / np.float32(np.iinfo(values.dtype).max)
    if len(values) != vertex_count:
        raise reader.fail(where, f"has {len(values)} values for {vertex_count} positions")
    outside = np.flatnonzero(~((values >= 0.0) & (values <= 1.0)).all(axis=1))
    if outside.size:
        vertex = int(outside[0])
        raise reader.fail(
            where, f"colour {values[vertex].tolist()} of vertex {vertex} is not in [0, 1] ({outside.size} vertices)"
        )
    colors = np.ones((len(values), 4), np.float32)
    colors[:, : values.shape[1]] = values
    return colors[faces]


def warn_unread_colors(reader: _Reader) -> None:
    """One SceneLoadWarning naming the COLOR_n attributes beyond COLOR_0 that the file's primitives
    carry, which are not read."""
    meshes = reader.document.get("meshes")
    primitives = [
        primitive
        for mesh in (meshes if isinstance(meshes, list) else [])
        if isinstance(mesh, dict) and isinstance(mesh.get("primitives"), list)
        for primitive in mesh["primitives"]
        if isinstance(primitive, dict) and isinstance(primitive.get("attributes"), dict)
    ]
    unread = sorted(
        {name for p in primitives for name in p["attributes"] if name.startswith("COLOR_") and name != COLOR_ATTRIBUTE}
    )
    if unread:
        warnings.warn(
            f"{reader.path}: vertex colours {', '.join(unread)} not read (only {COLOR_ATTRIBUTE} is): ignored",
            SceneLoadWarning,
            stacklevel=4,
        )
