"""Emitter: a diffuse area light that emits from both sides and reflects nothing.

| parameter | type       | default | meaning                                             |
|-----------|------------|---------|-----------------------------------------------------|
| color     | RGB >= 0   | 1       | spectrum of the emitted light                       |
| emittance | float >= 0 | 1       | scale: emitted radiance = color x emittance          |

The radiance (each component of color x emittance) is at most RADIANCE_MAX.

GPU record: color = the radiance. No WGSL file: it has no BSDF, and a path ends on it.
Mitsuba 3: an `area` emitter with radiance color x emittance on each side, and a black BSDF.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..registry import mitsuba_rgb
from .material import Material, MaterialError

# Far above any physical source (the sun's radiance is ~2e7 W/(sr m^2)), and low enough that the
# float32 sums of billions of samples per pixel on the GPU stay finite (float32 ends at 3.4e38).
RADIANCE_MAX = 1e20


@dataclass(eq=False)
class Emitter(Material):
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    emittance: float = 1.0

    kind = 1
    emission_wgsl = "material.color"

    def checked_parameters(self) -> dict[str, object]:
        color = self.check_color("color", self.color, upper=None)
        emittance = self.check_number("emittance", self.emittance, low=0.0, high=float("inf"))
        if max(color) * emittance > RADIANCE_MAX:
            raise MaterialError(
                f"material {self.name!r}: radiance color x emittance = {max(color) * emittance:.3g} exceeds "
                f"RADIANCE_MAX = {RADIANCE_MAX:g} (color {color}, emittance {emittance})",
                "emittance",
            )
        return {"color": color, "emittance": emittance}

    @property
    def radiance(self) -> tuple[float, float, float]:
        r, g, b = self.color
        return (r * self.emittance, g * self.emittance, b * self.emittance)

    def emits(self) -> bool:
        return max(self.radiance) > 0

    def fill_record(self, record) -> None:
        record["color"] = self.radiance

    @classmethod
    def record_radiance(cls, records: np.ndarray) -> np.ndarray:
        return records["color"].astype(np.float64)

    def mitsuba_emitter(self) -> dict:
        return {"type": "area", "radiance": mitsuba_rgb(self.radiance)}
