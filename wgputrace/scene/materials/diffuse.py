"""Diffuse: a Lambertian reflector, the same on both sides.

| parameter | type           | default | meaning                                   |
|-----------|----------------|---------|-------------------------------------------|
| color     | RGB in [0, 1]  | 0.5     | albedo: the fraction of light reflected   |

GPU record: color. WGSL: `diffuse_sample`, `diffuse_eval`, `diffuse_pdf`.
Mitsuba 3: `twosided` `diffuse` with `reflectance` = color (times vertex colours: `mitsuba_color`).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..registry import mitsuba_rgb
from .material import Material, MaterialShader


@dataclass(eq=False)
class Diffuse(Material):
    color: tuple[float, float, float] = (0.5, 0.5, 0.5)

    kind = 2
    mitsuba_color = "reflectance"
    shader = MaterialShader(
        "materials/diffuse.wgsl",
        sample="diffuse_sample(material.color, wi, u)",
        eval="diffuse_eval(material.color, wi, wo)",
        pdf="diffuse_pdf(wi, wo)",
    )

    def checked_parameters(self) -> dict[str, object]:
        return {"color": self.check_color("color", self.color, upper=1.0)}

    def fill_record(self, record) -> None:
        record["color"] = self.color

    def mitsuba_bsdf(self) -> dict:
        return {"type": "diffuse", "reflectance": mitsuba_rgb(self.color)}
