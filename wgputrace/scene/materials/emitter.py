"""Emitter: a diffuse area light that emits from both sides and reflects nothing.

| parameter | type       | default | meaning                                             |
|-----------|------------|---------|-----------------------------------------------------|
| color     | RGB >= 0   | 1       | spectrum of the emitted light                       |
| emittance | float >= 0 | 1       | scale: emitted radiance = color x emittance          |

Mitsuba 3: an `area` emitter with radiance color x emittance on each side, and a black BSDF.
"""

from __future__ import annotations

from dataclasses import dataclass

from .material import Material, MaterialKind, check_color, check_number


@dataclass(eq=False)
class Emitter(Material):
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    emittance: float = 1.0

    kind = MaterialKind.EMITTER

    def __post_init__(self) -> None:
        self.color = check_color(self.name, "color", self.color, upper=None)
        self.emittance = check_number(self.name, "emittance", self.emittance, low=0.0, high=float("inf"))

    @property
    def radiance(self) -> tuple[float, float, float]:
        r, g, b = self.color
        return (r * self.emittance, g * self.emittance, b * self.emittance)

    def gpu_parameters(self):
        return self.radiance, 0.0, 1.0
