"""glTF's KHR_materials_volume: absorption inside a transmissive material (`volume`), read into
Principled's attenuation parameters.

| KHR_materials_volume field          | read as                                                        |
|-------------------------------------|----------------------------------------------------------------|
| `attenuationColor` (default 1, 1, 1) | attenuation_color, each in [0, 1]                             |
| `attenuationDistance` (default infinite) | attenuation_distance, > 0, in world units (as glTF gives it) |
| `thicknessFactor` (default 0)       | 0: thin-walled, nothing absorbed; > 0: the mesh is a volume, its value not needed |
| `thicknessTexture`                  | ignored: a path tracer traces the real distance inside         |

As the specification says, a thicknessFactor of 0 makes the material thin-walled (no volume
behind its surface), and a volume acts only where light goes inside, with
KHR_materials_transmission: on any other material it is ignored. Out-of-range values are a
SceneLoadError naming the field's JSON path.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .gltf import _Reader

VOLUME_EXTENSION = "KHR_materials_volume"


def volume_parameters(reader: _Reader, extensions: dict, material_where: str) -> dict[str, object]:
    """Principled's attenuation_color and attenuation_distance from a material's `extensions`
    (at `material_where`.extensions), none where it has no volume or a thin wall."""
    where = f"{material_where}.extensions"
    if VOLUME_EXTENSION not in extensions:
        return {}
    block = reader.get(extensions, VOLUME_EXTENSION, dict, where)
    where = f"{where}.{VOLUME_EXTENSION}"
    color = reader.numbers(block, "attenuationColor", 3, where, [1.0, 1.0, 1.0])
    if color.min() < 0.0 or color.max() > 1.0:
        raise reader.fail(f"{where}.attenuationColor", f"must be in [0, 1], got {color.tolist()}")
    distance = reader.get(block, "attenuationDistance", float, where, math.inf)
    if not distance > 0.0:
        raise reader.fail(f"{where}.attenuationDistance", f"must be > 0, got {distance!r}")
    thickness = reader.get(block, "thicknessFactor", float, where, 0.0)
    if not thickness >= 0.0:
        raise reader.fail(f"{where}.thicknessFactor", f"must be >= 0, got {thickness!r}")
    if thickness == 0.0:
        return {}
    return {"attenuation_color": tuple(color.tolist()), "attenuation_distance": distance}
