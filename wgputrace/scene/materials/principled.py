"""Principled: Mitsuba 3's `principled` BSDF for the parameters glTF's metallic-roughness materials
need (transmission included).

| parameter  | type          | default | meaning                                                          |
|------------|---------------|---------|------------------------------------------------------------------|
| base_color | RGB in [0, 1] | 0.5     | diffuse albedo, and the metallic Fresnel reflectance at normal incidence (x the shape's vertex colours) |
| metallic   | float [0, 1]  | 0       | blends a dielectric (0) into a Schlick conductor tinted by base_color (1) |
| roughness  | float [0, 1]  | 0.5     | GGX alpha = roughness^2 (at least 0.001); also drives retro-reflection |
| eta        | float > 0     | 1.5     | index of refraction of the specular layer (Mitsuba's `specular` s is eta_from_specular(s)) |
| spec_trans | float [0, 1]  | 0       | weight of rough dielectric transmission (glTF KHR_materials_transmission); above 0 the back side is the inside |
| base_color_texture | Texture (sRGB) or None | None | RGB x base_color (glTF baseColorTexture); its alpha x alpha |
| metallic_roughness_texture | Texture (linear) or None | None | G x roughness, B x metallic (glTF metallicRoughnessTexture) |
| normal_texture | Texture (linear) or None | None | tangent-space normal map (glTF normalTexture; `mapped_normal`) |
| normal_scale | float [-100, 100] | 1 | x and y of the normal map's vectors x this (glTF normalTexture.scale) |
| alpha      | float [0, 1]  | 1       | coverage x the base colour texture's alpha x the shape's vertex alpha (alpha_mode: cut-outs, blending) |
| alpha_mode | "OPAQUE", "MASK", "BLEND" | "OPAQUE" | glTF's: alpha ignored; texels of alpha < alpha_cutoff cut out; stochastic transparency |
| alpha_cutoff | float [0, 1] | 0.5    | MASK's threshold                                                  |
| double_sided | bool       | True    | False: the surface is invisible from behind (its back face culled, as glTF viewers do) |
| emission   | RGB >= 0      | 0       | emitted radiance (glTF emissiveFactor), on both sides unless single-sided |
| emission_texture | Texture (sRGB) or None | None | RGB x emission (glTF emissiveTexture) |
| emission_strength | float >= 0 | 1    | x emission (KHR_materials_emissive_strength)                     |
| attenuation_color | RGB in [0, 1] | 1  | with spec_trans > 0, Beer-Lambert absorption inside: white light has this colour ... |
| attenuation_distance | float > 0 | inf | ... after this distance inside (KHR_materials_volume; `volume`)  |
| clearcoat  | float [0, 1]  | 0       | weight of a second, colourless GTR1 reflection (Schlick Fresnel of normal reflectance 0.04) on top |
| clearcoat_gloss | float [0, 1] | 0   | the clearcoat's GTR1 alpha = lerp(0.1, 0.001, clearcoat_gloss)   |
| sheen      | float [0, 1]  | 0       | weight of Disney's sheen: Schlick's (1 - cos_d)^5 retro-reflection at grazing angles, x (1 - metallic) |
| sheen_tint | float [0, 1]  | 0       | blends the sheen's colour from white to base_color's hue (base_color / its luminance) |
| anisotropic | float [0, 1] | 0       | GGX alpha_u = roughness^2 / aspect along the tangent, alpha_v = roughness^2 aspect, aspect = sqrt(1 - 0.9 anisotropic) (each at least 0.001) |
| anisotropy_rotation | float [-2 pi, 2 pi] | 0 | radians from the tangent towards the bitangent of the direction alpha_u runs along (glTF's anisotropyRotation; not Mitsuba's) |

A Disney diffuse lobe with retro-reflection, weighted by (1 - metallic)(1 - spec_trans), plus GGX
reflection whose Fresnel term is (1 - metallic) exact dielectric Fresnel + metallic
Schlick(base_color), plus rough dielectric transmission weighted by (1 - metallic) spec_trans and
tinted sqrt(base_color), plus from outside Mitsuba's clearcoat (0.25 clearcoat F D G cos_o: no
1 / (4 cos_i cos_o), as Mitsuba's has none) and sheen (sampled by the other lobes). Sampling picks
the diffuse lobe, the clearcoat (a GTR1 normal) and the GGX lobes at the rates (1 - metallic)(1 -
spec_trans), 0.25 clearcoat and 1 (the GGX one split into reflection and refraction by its Fresnel
and spec_trans: a visible GGX normal reflects or refracts). Without transmission the material is
the same on both sides (Mitsuba's `twosided`); with it, its back is the inside (eta seen from there is 1 / eta).
With anisotropic > 0 both GGX lobes (reflection and transmission) are Mitsuba's anisotropic GGX, in
a frame whose first axis is the surface tangent (`surface_frame`: the mesh's tangents, a file's
TANGENT or MikkTSpace's from its texture coordinates, as normal maps take them; where a mesh has no
texture coordinates, Mitsuba's fallback, the first axis of `coordinate_system` of the triangle's
normal), turned by anisotropy_rotation.
GPU record: color = base_color, alpha = roughness, ior = eta, metallic, spec_trans, clearcoat,
clearcoat_gloss, sheen, sheen_tint, anisotropic, absorption
(sigma_a, 0 without transmission: nothing goes inside); the clearcoat, sheen and anisotropy code is compiled only into kernels of
scenes with a material that uses it (`lobes`, `principled_lobes_hook`). Textures, alpha
and normal_scale are in its MATERIAL_TEXTURES record, applied at the hit (`resolve_material`) so
the BSDF code sees constants; alpha modes and sidedness act in the traversal's triangle test
(`surface_blocks`), compiled only for scenes with such a material. WGSL: `principled_sample`,
`principled_eval`, `principled_pdf`. Mitsuba 3: `principled` with the same values, in `twosided`
without transmission; an interior `homogeneous` medium where it absorbs (`mitsuba_medium`).
Mitsuba's spec_tint and flatness are not here; anisotropy_rotation is not Mitsuba's (its tangent is
dP/du: `mitsuba_bsdf` refuses a turned one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..registry import mitsuba_rgb
from ..texture import Texture
from .emitter import RADIANCE_MAX
from .glass import IOR_MAX
from .material import ALPHA_MODES, Material, MaterialError, MaterialShader
from .volume import absorption_coefficients, checked_attenuation

# the optional lobes (each switched on by its weight's parameter) and the parameters of their records
PRINCIPLED_LOBES = ("clearcoat", "sheen", "anisotropic")
_LOBE_PARAMETERS = ("clearcoat", "clearcoat_gloss", "sheen", "sheen_tint", "anisotropic")
# the texture parameters, `<slot>_texture` for each MATERIAL_TEXTURES slot Principled reads
_TEXTURE_SLOTS = ("base_color", "metallic_roughness", "normal", "emission")
# glTF sets no bound on a normal map's scale; beyond this its bumps are all slope (a typo, surely)
NORMAL_SCALE_MAX = 100.0


def eta_from_specular(specular: float) -> float:
    """Mitsuba's (and Disney's) mapping of `specular` in [0, 1] to an index of refraction:
    Schlick's normal reflectance 0.08 specular; specular 0.5 is eta 1.5."""
    return 2.0 / (1.0 - math.sqrt(0.08 * specular)) - 1.0


@dataclass(eq=False)
class Principled(Material):
    base_color: tuple[float, float, float] = (0.5, 0.5, 0.5)
    metallic: float = 0.0
    roughness: float = 0.5
    eta: float = 1.5
    spec_trans: float = 0.0
    base_color_texture: Texture | None = None
    metallic_roughness_texture: Texture | None = None
    normal_texture: Texture | None = None
    normal_scale: float = 1.0
    alpha: float = 1.0
    alpha_mode: str = "OPAQUE"
    alpha_cutoff: float = 0.5
    double_sided: bool = True
    emission: tuple[float, float, float] = (0.0, 0.0, 0.0)
    emission_texture: Texture | None = None
    emission_strength: float = 1.0
    attenuation_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    attenuation_distance: float = math.inf
    clearcoat: float = 0.0
    clearcoat_gloss: float = 0.0
    sheen: float = 0.0
    sheen_tint: float = 0.0
    anisotropic: float = 0.0
    anisotropy_rotation: float = 0.0

    kind = 5
    shader = MaterialShader(
        "materials/principled.wgsl",
        sample="principled_sample(material, wi, u, u_lobe)",
        eval="principled_eval(material, wi, wo)",
        pdf="principled_pdf(material, wi, wo)",
    )

    # two-sided (Mitsuba's `twosided`) without transmission; with it the back is the inside
    two_sided_wgsl = "material.spec_trans == 0.0"

    def checked_parameters(self) -> dict[str, object]:
        for slot in _TEXTURE_SLOTS:
            parameter = f"{slot}_texture"
            value = getattr(self, parameter)
            if value is not None and not isinstance(value, Texture):
                raise MaterialError(
                    f"material {self.name!r}: {parameter} must be a Texture or None, got {type(value).__name__}",
                    parameter,
                )
        if self.alpha_mode not in ALPHA_MODES:
            raise MaterialError(
                f"material {self.name!r}: alpha_mode must be one of {', '.join(ALPHA_MODES)}, got {self.alpha_mode!r}",
                "alpha_mode",
            )
        if not isinstance(self.double_sided, bool):
            raise MaterialError(
                f"material {self.name!r}: double_sided must be True or False, got {self.double_sided!r}", "double_sided"
            )
        return {
            "alpha": self.check_number("alpha", self.alpha, low=0.0, high=1.0),
            "alpha_mode": self.alpha_mode,
            "alpha_cutoff": self.check_number("alpha_cutoff", self.alpha_cutoff, low=0.0, high=1.0),
            "double_sided": self.double_sided,
            "emission": self.check_color("emission", self.emission, upper=None),
            "emission_strength": self.check_number(
                "emission_strength", self.emission_strength, low=0.0, high=RADIANCE_MAX
            ),
            "base_color": self.check_color("base_color", self.base_color, upper=1.0),
            "metallic": self.check_number("metallic", self.metallic, low=0.0, high=1.0),
            "spec_trans": self.check_number("spec_trans", self.spec_trans, low=0.0, high=1.0),
            "roughness": self.check_number("roughness", self.roughness, low=0.0, high=1.0),
            "eta": self.check_number("eta", self.eta, low=0.0, high=IOR_MAX, low_inclusive=False),
            "normal_scale": self.check_number(
                "normal_scale", self.normal_scale, low=-NORMAL_SCALE_MAX, high=NORMAL_SCALE_MAX
            ),
            "anisotropy_rotation": self.check_number(
                "anisotropy_rotation", self.anisotropy_rotation, low=-math.tau, high=math.tau
            ),
            **checked_attenuation(self, self.attenuation_color, self.attenuation_distance),
            **{name: self.check_number(name, getattr(self, name), low=0.0, high=1.0) for name in _LOBE_PARAMETERS},
        }

    def fill_record(self, record) -> None:
        record["color"], record["alpha"] = self.base_color, self.roughness
        record["ior"], record["metallic"] = self.eta, self.metallic
        record["spec_trans"] = self.spec_trans
        for name in _LOBE_PARAMETERS:
            record[name] = getattr(self, name)

    def lobes(self) -> frozenset[str]:
        return frozenset(lobe for lobe in PRINCIPLED_LOBES if getattr(self, lobe) > 0)

    def reads_tangent(self) -> bool:
        return self.anisotropic > 0

    def absorption(self) -> tuple[float, float, float]:
        if self.spec_trans == 0.0:
            return super().absorption()
        return absorption_coefficients(self.attenuation_color, self.attenuation_distance)

    def textures(self) -> dict[str, Texture]:
        slots = {slot: getattr(self, f"{slot}_texture") for slot in _TEXTURE_SLOTS}
        return {slot: texture for slot, texture in slots.items() if texture is not None}

    def lets_rays_through(self) -> bool:
        return self.alpha_mode != "OPAQUE" or not self.double_sided

    def surface_emission(self) -> tuple[float, float, float]:
        return tuple(c * self.emission_strength for c in self.emission)

    def fill_texture_record(self, record) -> None:
        record["alpha"], record["alpha_mode"] = self.alpha, ALPHA_MODES.index(self.alpha_mode)
        record["alpha_cutoff"], record["double_sided"] = self.alpha_cutoff, self.double_sided
        record["emitted"], record["normal_scale"] = self.surface_emission(), self.normal_scale
        record["anisotropy_rotation"] = self.anisotropy_rotation

    def mitsuba_bsdf(self, tangent_handedness: float = 1.0) -> dict:
        """Textured parameters become `bitmap`s of the texels times their factor (the product the
        GPU forms after filtering, which bilinear filtering leaves the same). A normal map becomes
        Mitsuba's `normalmap` wrapper (normal_map_texels) without its terminator term (compare with
        ours off: MITSUBA_SHADING_NORMALS): `tangent_handedness` is the w of the
        triangles' tangents, which the material does not know. MASK and BLEND wrap the whole in
        Mitsuba's `mask` (mitsuba_opacity). Sidedness is not exported: a single-sided surface renders
        alike from its front (`twosided` differs only from behind); emission is mitsuba_emitter's."""
        bsdf = {
            "type": "principled",
            "base_color": mitsuba_rgb(self.base_color),
            "metallic": self.metallic,
            "roughness": self.roughness,
            "eta": self.eta,
        }
        # Mitsuba switches its transmission, clearcoat, sheen, sheen tint and anisotropy on by their keys' presence
        if self.spec_trans > 0:
            bsdf["spec_trans"] = self.spec_trans
        if self.anisotropic > 0:
            if self.anisotropy_rotation != 0:
                raise MaterialError(
                    f"{self.label}: anisotropy_rotation {self.anisotropy_rotation:g} has no Mitsuba 3 parameter "
                    "(its anisotropy follows dP/du: turn the texture coordinates instead)",
                    "anisotropy_rotation",
                )
            bsdf["anisotropic"] = self.anisotropic
        if self.clearcoat > 0:
            bsdf |= {"clearcoat": self.clearcoat, "clearcoat_gloss": self.clearcoat_gloss}
        if self.sheen > 0:
            bsdf["sheen"] = self.sheen
            if self.sheen_tint > 0:
                bsdf["sheen_tint"] = self.sheen_tint
        base, metallic_roughness = self.base_color_texture, self.metallic_roughness_texture
        if base is not None:
            bsdf["base_color"] = base.mitsuba_bitmap(base.linear_texels[..., :3] * self.base_color)
        if metallic_roughness is not None:
            texels = metallic_roughness.linear_texels
            bsdf["roughness"] = metallic_roughness.mitsuba_bitmap(texels[..., 1:2] * self.roughness)
            bsdf["metallic"] = metallic_roughness.mitsuba_bitmap(texels[..., 2:3] * self.metallic)
        normal = self.normal_texture
        if normal is not None:
            texels = normal_map_texels(normal.linear_texels[..., :3], self.normal_scale, tangent_handedness)
            # Mitsuba's terminator term for bumps (Estevez et al. 2019, on by default since 3.7.1) is
            # not ours (Chiang et al. 2019): both off, the references test what they share
            bsdf = {
                "type": "normalmap",
                "normalmap": normal.mitsuba_bitmap(texels),
                "use_shadowing_function": False,
                "bsdf": bsdf,
            }
        if self.alpha_mode != "OPAQUE":
            bsdf = {"type": "mask", "opacity": self.mitsuba_opacity(), "bsdf": bsdf}
        return bsdf

    def mitsuba_opacity(self) -> dict | float:
        """The alpha mode as Mitsuba's `mask` opacity (the probability that a ray meets the surface).

        MASK: 1 where alpha x the texel's alpha reaches alpha_cutoff, else 0, looked up nearest. The
        GPU thresholds the bilinear alpha instead, which cuts at the same texel boundaries only where
        neighbouring texels are 0 and 1 about a cutoff of 0.5 (as the stripes of the alpha_cutout
        scene are); elsewhere the edges differ by under a texel.
        BLEND: alpha x the texel's alpha, bilinear as the GPU looks it up: the probability with which
        stochastic transparency stops a ray, so Mitsuba's `mask` renders its expectation."""
        base = self.base_color_texture
        alpha = self.alpha if base is None else self.alpha * base.linear_texels[..., 3:4]
        if self.alpha_mode == "BLEND":
            return float(alpha) if base is None else base.mitsuba_bitmap(alpha.astype(np.float32))
        if base is None:
            return float(alpha >= self.alpha_cutoff)
        return base.mitsuba_bitmap((alpha >= self.alpha_cutoff).astype(np.float32)) | {"filter_type": "nearest"}

    def mitsuba_emitter(self) -> dict | None:
        """An `area` emitter of emission x strength, times the texture's texels as a `bitmap`
        radiance where there is one; None where the material emits nothing."""
        emitted = np.asarray(self.emission, np.float64) * self.emission_strength
        if emitted.max() <= 0:
            return None
        texture = self.emission_texture
        if texture is None:
            return {"type": "area", "radiance": mitsuba_rgb(emitted)}
        return {"type": "area", "radiance": texture.mitsuba_bitmap(texture.linear_texels[..., :3] * emitted)}


def normal_map_texels(texels: np.ndarray, scale: float, tangent_handedness: float) -> np.ndarray:
    """glTF normal-map texels as Mitsuba's `normalmap` reads them. glTF's green runs along the
    bitangent w (n x t); Mitsuba's along n x dP/du, the same axis times w: green is flipped where
    w = -1. normal_scale multiplies x and y before normalising (glTF), as Mitsuba normalises after
    filtering: baked into the texels, which stay linear in the stored value, so filtering agrees."""
    vectors = 2.0 * np.asarray(texels, np.float64) - 1.0
    vectors[..., :2] *= scale
    vectors[..., 1] *= tangent_handedness
    return (0.5 * (vectors + 1.0)).astype(np.float32)
