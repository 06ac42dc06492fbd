"""Glass: a smooth dielectric interface with exact Fresnel and total internal reflection.

| parameter | type          | default | meaning                                                      |
|-----------|---------------|---------|--------------------------------------------------------------|
| color     | RGB in [0, 1] | 1       | tints transmission only (applied at every crossing)          |
| ior       | float > 0     | 1.5     | index of refraction inside; outside is 1                     |
| attenuation_color | RGB in [0, 1] | 1 | Beer-Lambert absorption inside: white light has this colour ... |
| attenuation_distance | float > 0 | inf | ... after this distance inside (glTF's KHR_materials_volume; `volume`) |

"Inside" is the side opposite the triangle's normal cross(v1 - v0, v2 - v0): closed meshes must
wind their triangles counter-clockwise seen from outside. Both lobes are deltas.
GPU record: color, ior, absorption (sigma_a). WGSL: `glass_sample`, `glass_eval`, `glass_pdf`.
Mitsuba 3: `dielectric` with `int_ior` = ior, `ext_ior` = 1, `specular_transmittance` = color; an
absorbing one also gets an interior `homogeneous` medium (`mitsuba_medium`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..registry import mitsuba_rgb
from .material import Material, MaterialShader
from .volume import absorption_coefficients, checked_attenuation

# An ior far outside every real material is almost always a unit or typing mistake.
IOR_MAX = 100.0


@dataclass(eq=False)
class Glass(Material):
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ior: float = 1.5
    attenuation_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    attenuation_distance: float = math.inf

    kind = 3
    shader = MaterialShader(
        "materials/glass.wgsl",
        sample="glass_sample(material.color, material.ior, wi, u_lobe)",
        eval="glass_eval(wi, wo)",
        pdf="glass_pdf(wi, wo)",
    )
    delta = True
    two_sided = False

    def checked_parameters(self) -> dict[str, object]:
        return {
            "color": self.check_color("color", self.color, upper=1.0),
            "ior": self.check_number("ior", self.ior, low=0.0, high=IOR_MAX, low_inclusive=False),
            **checked_attenuation(self, self.attenuation_color, self.attenuation_distance),
        }

    def absorption(self) -> tuple[float, float, float]:
        return absorption_coefficients(self.attenuation_color, self.attenuation_distance)

    def fill_record(self, record) -> None:
        record["color"], record["ior"] = self.color, self.ior

    def mitsuba_bsdf(self) -> dict:
        return {
            "type": "dielectric",
            "int_ior": self.ior,
            "ext_ior": 1.0,
            "specular_transmittance": mitsuba_rgb(self.color),
        }
