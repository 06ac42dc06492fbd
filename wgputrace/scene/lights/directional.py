"""DirectionalLight: light arriving from one direction everywhere, as from an infinitely far point.

| parameter  | type        | default | meaning                                                 |
|------------|-------------|---------|---------------------------------------------------------|
| direction  | 3 numbers   |         | the way the light travels (normalised; not zero)        |
| irradiance | float >= 0  |         | irradiance on a surface facing it (W/m^2)               |
| color      | RGB >= 0    | 1       | spectrum: irradiance = color x irradiance               |

A delta light: reached by light sampling only (weight 1 under every integrator), shadow rays run to
infinity. GPU record: direction, emission = color x irradiance. WGSL: `directional_light_sample`.
Mitsuba 3: `directional` with `direction` and `irradiance` = color x irradiance.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..registry import mitsuba_rgb
from .light import Light, LightShader, luminance


@dataclass(eq=False)
class DirectionalLight(Light):
    direction: tuple[float, float, float]
    irradiance: float
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    name: str = ""

    kind = 1
    shader = LightShader(
        "lights/directional.wgsl",
        sample="directional_light_sample(light, p)",
        emission_sample="directional_emission_sample(light, disk, u_position)",
    )
    delta = True
    distant = True
    strength = "irradiance"

    def checked_placement(self) -> dict[str, object]:
        return {"direction": self.check_vector("direction", self.direction, unit=True)}

    def fill_record(self, record) -> None:
        record["direction"], record["emission"] = self.direction, self.rgb_strength

    def weight(self, scene_radius: float) -> float:
        # the irradiance over a disc of the scene's radius, over the 2 pi of the triangles' units
        return luminance(self.rgb_strength) * scene_radius**2 / 2.0

    def mitsuba_emitter(self) -> dict:
        return {"type": "directional", "direction": list(self.direction), "irradiance": mitsuba_rgb(self.rgb_strength)}
