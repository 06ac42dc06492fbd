"""DirectionalLight: light arriving from one direction everywhere, as from an infinitely far point.

| parameter  | type        | default | meaning                                                 |
|------------|-------------|---------|---------------------------------------------------------|
| direction  | 3 numbers   |         | the way the light travels (normalised; not zero)        |
| irradiance | float >= 0  |         | irradiance on a surface facing it (W/m^2)               |
| color      | RGB >= 0    | 1       | spectrum: irradiance = color x irradiance               |

A delta light: reached by light sampling only (weight 1 under every integrator), shadow rays run to
infinity. GPU record: direction, emission = color x irradiance. WGSL: shaders/lights/directional.wgsl.
Mitsuba 3: `directional` with `direction` and `irradiance` = color x irradiance.
"""

from __future__ import annotations

from dataclasses import dataclass

from .light import Light, LightShader, luminance, mitsuba_rgb, scaled


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

    def checked_parameters(self) -> dict[str, object]:
        color = self.check_color("color", self.color)
        return {
            "direction": self.check_vector("direction", self.direction, unit=True),
            "irradiance": self.check_strength("irradiance", self.irradiance, color),
            "color": color,
        }

    def fill_record(self, record) -> None:
        record["direction"] = self.direction
        record["emission"] = scaled(self.color, self.irradiance)

    def weight(self, scene_radius: float) -> float:
        # the irradiance over a disc of the scene's radius, over the 2 pi of the triangles' units
        return luminance(scaled(self.color, self.irradiance)) * scene_radius**2 / 2.0

    def mitsuba_emitter(self) -> dict:
        return {
            "type": "directional",
            "direction": list(self.direction),
            "irradiance": mitsuba_rgb(scaled(self.color, self.irradiance)),
        }
