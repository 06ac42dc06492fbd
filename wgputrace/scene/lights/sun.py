"""Sun: a distant disc of uniform radiance, sampled by its cone (soft shadows).

| parameter                | type        | default | meaning                                            |
|--------------------------|-------------|---------|----------------------------------------------------|
| direction                | 3 numbers   |         | the way the sunlight travels (normalised)          |
| irradiance               | float >= 0  |         | irradiance at normal incidence (W/m^2)             |
| angular_diameter_degrees | (0, 90]     | 0.53    | the disc's angular diameter (the sun's: 0.53)      |
| color                    | RGB >= 0    | 1       | spectrum: irradiance = color x irradiance          |

The radiance inside the disc is L = E / (pi sin^2(d / 2)), so that L cos integrated over the disc
seen head-on is E. Not a delta: light sampling draws a direction uniformly in the cone, and rays
escaping the scene inside the cone see L, weighted against it by MIS as emissive triangles are.
Its shadow rays run to infinity. GPU record: direction, emission = L x color, cos_outer = cos(d / 2)
and cone = 1 - cos(d / 2) (in float64 on the host: 1.07e-5 for the sun, where f32 would keep 3
digits). WGSL: `sun_sample`. Mitsuba 3 has no sun-disc plugin of this form
(`mitsuba_emitter` is None); reference scenes draw it into an `envmap`, or use the closed form.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .light import Light, LightShader, luminance, scaled

SUN_ANGULAR_DIAMETER_DEGREES = 0.53


@dataclass(eq=False)
class Sun(Light):
    direction: tuple[float, float, float]
    irradiance: float
    angular_diameter_degrees: float = SUN_ANGULAR_DIAMETER_DEGREES
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    name: str = ""

    kind = 2
    shader = LightShader(
        "lights/sun.wgsl",
        sample="sun_sample(light, p, u)",
        escaped_radiance="sun_escaped_radiance(light, direction)",
        escaped_pdf="sun_pdf(light, direction)",
        emission_sample="sun_emission_sample(light, disk, u_position, u_direction)",
    )
    distant = True
    strength = "irradiance"

    def checked_placement(self) -> dict[str, object]:
        diameter = self.check_number(
            "angular_diameter_degrees", self.angular_diameter_degrees, low=0, high=90, low_inclusive=False
        )
        return {
            "direction": self.check_vector("direction", self.direction, unit=True),
            "angular_diameter_degrees": diameter,
        }

    @property
    def radiance(self) -> tuple[float, float, float]:
        """The radiance inside the disc: E / (pi sin^2(d / 2)) x color."""
        half = math.radians(self.angular_diameter_degrees) / 2.0
        return scaled(self.color, self.irradiance / (math.pi * math.sin(half) ** 2))

    def fill_record(self, record) -> None:
        half = math.radians(self.angular_diameter_degrees) / 2.0
        record["direction"] = self.direction
        record["emission"] = self.radiance
        record["cos_outer"] = math.cos(half)
        record["cone"] = 2.0 * math.sin(half / 2.0) ** 2  # 1 - cos(half), without cancellation

    def weight(self, scene_radius: float) -> float:
        # as a directional light of the same irradiance
        return luminance(self.rgb_strength) * scene_radius**2 / 2.0

    def mitsuba_emitter(self) -> None:
        return None
