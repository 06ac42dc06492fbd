"""Glossy: a rough conductor with a GGX microfacet distribution, the same on both sides.

| parameter | type          | default | meaning                                                        |
|-----------|---------------|---------|----------------------------------------------------------------|
| color     | RGB in [0, 1] | 1       | Fresnel reflectance (constant: Fresnel = 1 tinted by color)     |
| roughness | float [0, 1]  | 0.1     | GGX alpha (not squared); 0 is clamped to a near-mirror          |

Sampling draws visible normals (Heitz 2018); shadowing is Smith's separable G1(wi) G1(wo).
Mitsuba 3: `twosided` `roughconductor`, `material`=`none`, `distribution`=`ggx`,
`alpha` = roughness, `specular_reflectance` = color, `sample_visible` = true.
"""

from __future__ import annotations

from dataclasses import dataclass

from .material import Material, MaterialKind, check_color, check_number


@dataclass(eq=False)
class Glossy(Material):
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    roughness: float = 0.1

    kind = MaterialKind.GLOSSY

    def checked_parameters(self) -> dict[str, object]:
        return {
            "color": check_color(self.name, "color", self.color, upper=1.0),
            "roughness": check_number(self.name, "roughness", self.roughness, low=0.0, high=1.0),
        }

    def gpu_parameters(self):
        return self.color, self.roughness, 1.0
