"""Glossy: a rough conductor with a GGX microfacet distribution, the same on both sides.

| parameter | type          | default | meaning                                                        |
|-----------|---------------|---------|----------------------------------------------------------------|
| color     | RGB in [0, 1] | 1       | Fresnel reflectance (constant: Fresnel = 1 tinted by color)     |
| roughness | float [0, 1]  | 0.1     | GGX alpha (not squared); 0 is clamped to a near-mirror          |

Sampling draws visible normals (Heitz 2018); shadowing is Smith's separable G1(wi) G1(wo).
Lobes narrower than GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS (a WGSL override) skip light sampling.
GPU record: color, alpha = roughness. WGSL: `glossy_sample`, `glossy_eval`, `glossy_pdf`.
Mitsuba 3: `twosided` `roughconductor`, `material`=`none`, `distribution`=`ggx`,
`alpha` = roughness, `specular_reflectance` = color (times vertex colours: `mitsuba_color`),
`sample_visible` = true.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..registry import mitsuba_rgb
from .material import Material, MaterialShader


@dataclass(eq=False)
class Glossy(Material):
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    roughness: float = 0.1

    kind = 4
    mitsuba_color = "specular_reflectance"
    shader = MaterialShader(
        "materials/glossy.wgsl",
        sample="glossy_sample(material.color, material.alpha, wi, u)",
        eval="glossy_eval(material.color, material.alpha, wi, wo)",
        pdf="glossy_pdf(material.alpha, wi, wo)",
    )
    samples_lights = "material.alpha >= GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS"

    def checked_parameters(self) -> dict[str, object]:
        return {
            "color": self.check_color("color", self.color, upper=1.0),
            "roughness": self.check_number("roughness", self.roughness, low=0.0, high=1.0),
        }

    def fill_record(self, record) -> None:
        record["color"], record["alpha"] = self.color, self.roughness

    def mitsuba_bsdf(self) -> dict:
        return {
            "type": "roughconductor",
            "material": "none",
            "distribution": "ggx",
            "sample_visible": True,
            "alpha": self.roughness,
            "specular_reflectance": mitsuba_rgb(self.color),
        }
