"""Diffuse: a Lambertian reflector, the same on both sides.

| parameter | type           | default | meaning                                   |
|-----------|----------------|---------|-------------------------------------------|
| color     | RGB in [0, 1]  | 0.5     | albedo: the fraction of light reflected   |

Mitsuba 3: `twosided` `diffuse` with `reflectance` = color.
"""

from __future__ import annotations

from dataclasses import dataclass

from .material import Material, MaterialKind, check_color


@dataclass(eq=False)
class Diffuse(Material):
    color: tuple[float, float, float] = (0.5, 0.5, 0.5)

    kind = MaterialKind.DIFFUSE

    def checked_parameters(self) -> dict[str, object]:
        return {"color": check_color(self.name, "color", self.color, upper=1.0)}

    def gpu_parameters(self):
        return self.color, 0.0, 1.0
