"""PointLight: an isotropic point source.

| parameter | type        | default | meaning                                                  |
|-----------|-------------|---------|----------------------------------------------------------|
| position  | 3 numbers   |         | where it is                                              |
| intensity | float >= 0  |         | radiant intensity (W/sr): irradiance I cos / d^2 at d    |
| color     | RGB >= 0    | 1       | spectrum: intensity = color x intensity                  |

A delta light: reached by light sampling only (weight 1 under every integrator). GPU record:
position, emission = color x intensity. WGSL: `point_light_sample`.
Mitsuba 3: `point` with `position` and `intensity` = color x intensity.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..registry import mitsuba_rgb
from .light import Light, LightShader, luminance


@dataclass(eq=False)
class PointLight(Light):
    position: tuple[float, float, float]
    intensity: float
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    name: str = ""

    kind = 3
    shader = LightShader(
        "lights/point.wgsl",
        sample="point_light_sample(light, p)",
        emission_sample="point_emission_sample(light, u_direction)",
        emission_pdf="point_emission_pdf(light, direction)",
    )
    delta = True
    strength = "intensity"

    def checked_placement(self) -> dict[str, object]:
        return {"position": self.check_vector("position", self.position, unit=False)}

    def fill_record(self, record) -> None:
        record["position"], record["emission"] = self.position, self.rgb_strength

    def weight(self, scene_radius: float) -> float:
        # 4 pi I over the 2 pi of the triangles' units
        return 2.0 * luminance(self.rgb_strength)

    def mitsuba_emitter(self) -> dict:
        return {"type": "point", "position": list(self.position), "intensity": mitsuba_rgb(self.rgb_strength)}
