"""SpotLight: a point source shining into a cone, with Mitsuba 3's falloff.

| parameter             | type          | default          | meaning                                      |
|-----------------------|---------------|------------------|----------------------------------------------|
| position              | 3 numbers     |                  | where it is                                  |
| direction             | 3 numbers     |                  | the cone's axis, the way the light travels   |
| intensity             | float >= 0    |                  | radiant intensity on the axis (W/sr)         |
| cutoff_angle_degrees  | (0, 90]       | 20               | half-angle of the cone: no light beyond it   |
| beam_width_degrees    | (0, cutoff]   | 3/4 of cutoff    | half-angle of full intensity                 |
| color                 | RGB >= 0      | 1                | spectrum: intensity = color x intensity      |

The intensity is full within beam_width of the axis and falls linearly in ANGLE to 0 at
cutoff_angle (Mitsuba's `spot`; glTF's KHR_lights_punctual falls off differently: the loader maps
its cone angles onto these). A delta light: reached by light sampling only (weight 1 under every
integrator). GPU record: position, direction, emission = color x intensity, the cosines of both
angles, the cutoff angle, 1 / (cutoff - beam width) and cone = 1 - cos(cutoff) (in float64 on the
host, for narrow cones: light paths leave uniformly within it). WGSL: `spot_light_sample`.
Mitsuba 3: `spot` with `intensity`, `cutoff_angle`, `beam_width` (degrees) and `to_world` looking
from position along direction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..registry import mitsuba_rgb
from .light import Light, LightError, LightShader, luminance

# Mitsuba's default beam width, as a fraction of the cutoff angle.
BEAM_WIDTH_FRACTION = 0.75
# 1 / (cutoff - beam width) is stored no larger than this: a beam as wide as its cutoff is a hard
# edge, and the falloff, clamped to 1, stays finite.
MAX_INVERSE_TRANSITION = 1e30


@dataclass(eq=False)
class SpotLight(Light):
    position: tuple[float, float, float]
    direction: tuple[float, float, float]
    intensity: float
    cutoff_angle_degrees: float = 20.0
    beam_width_degrees: float | None = None
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    name: str = ""

    kind = 4
    shader = LightShader(
        "lights/spot.wgsl",
        sample="spot_light_sample(light, p)",
        emission_sample="spot_emission_sample(light, u_direction)",
        emission_pdf="spot_emission_pdf(light, direction)",
    )
    delta = True
    strength = "intensity"

    def checked_placement(self) -> dict[str, object]:
        cutoff = self.check_number(
            "cutoff_angle_degrees", self.cutoff_angle_degrees, low=0, high=90, low_inclusive=False
        )
        beam = cutoff * BEAM_WIDTH_FRACTION if self.beam_width_degrees is None else self.beam_width_degrees
        beam = self.check_number("beam_width_degrees", beam, low=0, high=90, low_inclusive=False)
        if beam > cutoff:
            raise LightError(
                f"{self.label}: beam_width_degrees {beam:g} is wider than cutoff_angle_degrees {cutoff:g}",
                "beam_width_degrees",
            )
        return {
            "position": self.check_vector("position", self.position, unit=False),
            "direction": self.check_vector("direction", self.direction, unit=True),
            "cutoff_angle_degrees": cutoff,
            "beam_width_degrees": None if self.beam_width_degrees is None else beam,
        }

    @property
    def beam_width(self) -> float:
        """The beam width in degrees, the default resolved."""
        return (
            self.cutoff_angle_degrees * BEAM_WIDTH_FRACTION
            if self.beam_width_degrees is None
            else self.beam_width_degrees
        )

    def fill_record(self, record) -> None:
        cutoff, beam = math.radians(self.cutoff_angle_degrees), math.radians(self.beam_width)
        record["position"] = self.position
        record["direction"] = self.direction
        record["emission"] = self.rgb_strength
        record["cos_outer"], record["cos_inner"] = math.cos(cutoff), math.cos(beam)
        record["angle_outer"] = cutoff
        record["cone"] = 2.0 * math.sin(cutoff / 2.0) ** 2  # 1 - cos(cutoff), without cancellation
        record["inverse_transition"] = (
            min(1.0 / (cutoff - beam), MAX_INVERSE_TRANSITION) if cutoff > beam else MAX_INVERSE_TRANSITION
        )

    def weight(self, scene_radius: float) -> float:
        # pbrt-v4's estimate: 2 pi I ((1 - cos beam) + (cos beam - cos cutoff) / 2), over 2 pi
        cos_cutoff, cos_beam = (
            math.cos(math.radians(self.cutoff_angle_degrees)),
            math.cos(math.radians(self.beam_width)),
        )
        return luminance(self.rgb_strength) * ((1.0 - cos_beam) + (cos_beam - cos_cutoff) / 2.0)

    def mitsuba_emitter(self) -> dict:
        position = np.asarray(self.position)
        # any up not along the axis: the cone is round
        up = (1.0, 0.0, 0.0) if abs(self.direction[1]) > 0.9 else (0.0, 1.0, 0.0)
        return {
            "type": "spot",
            "to_world": {
                "look_at": {"origin": list(self.position), "target": list(position + self.direction), "up": list(up)}
            },
            "intensity": mitsuba_rgb(self.rgb_strength),
            "cutoff_angle": self.cutoff_angle_degrees,
            "beam_width": self.beam_width,
        }
