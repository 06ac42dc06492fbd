"""The base of every material and the registry of material kinds.

A material kind is one class in one module of this package, plus its WGSL file if it reflects
light, and nothing else: like a Mitsuba 3 BSDF plugin, the class is the whole descriptor, and like
pbrt-v4's `BxDF::Flags()` it answers what the integrator asks.

| what                                    | on the class                     | driven from it                                  |
|-----------------------------------------|----------------------------------|-------------------------------------------------|
| the id the GPU switches on              | `kind`                           | `MATERIAL_<NAME>` constants, the records' kind  |
| parameters and their checks             | dataclass fields, `checked_parameters` | editing re-checks (`__setattr__`)          |
| its GPU record                          | `fill_record`                    | `material_records`                              |
| its BSDF code (sample, eval, pdf)       | `shader`                         | `material_dispatch`: generated dispatch         |
| optional lobes it uses (clearcoat, ...) | `lobes`                          | `SceneFeatures.lobes`: their code compiled in   |
| does its BSDF turn about the normal?    | `reads_tangent`                  | tangents uploaded, `surface_frame` along them   |
| every lobe a delta?                     | `delta`                          | the default of `samples_lights`                 |
| can a light sample land in its lobe?    | `samples_lights` (WGSL)          | `material_samples_lights`: next-event estimation |
| the same BSDF seen from both sides?     | `two_sided`                      | `material_is_two_sided`; the Mitsuba `twosided` wrapper |
| the radiance it emits                   | `emission_wgsl`, `record_radiance` | `material_emitted`, `light_table`             |
| absorption of the light inside it       | `absorption`                     | its record's absorption, `segment_transmittance` |
| its Mitsuba 3 equivalent                | `mitsuba_bsdf`, `mitsuba_emitter` | `mitsuba_scene`                                |

A class registers itself as a kind when its body sets `kind`; subclassing a kind without setting
one makes a variant of that kind. Emission shines from both sides of a triangle; a kind without
`shader` reflects nothing, and a path ends on it. Assigning a parameter re-runs the material's
checks (MaterialError leaves the material as it was) and bumps `version`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..registry import Kind, KindRegistry, ParameterError, finite_non_negative, rgb_values
from ..texture import Texture

# glTF's alphaMode values, numbered for the GPU in this order (a MATERIAL_TEXTURES record's alpha_mode)
ALPHA_MODES = ("OPAQUE", "MASK", "BLEND")


class MaterialError(ParameterError):
    """A material parameter is out of its documented range; `parameter` names it."""


@dataclass(frozen=True)
class MaterialShader:
    """A kind's BSDF code: its file under shaders/ and the WGSL calls the generated dispatch makes
    into it. The calls see `material` (its Material record), `wi`, `wo`, `u` (vec2) and `u_lobe`."""

    file: str
    sample: str
    eval: str
    pdf: str


def _check_kind(cls: type[Material], where: str) -> None:
    if cls.shader is not None and not isinstance(cls.shader, MaterialShader):
        raise TypeError(f"{where}: shader must be a MaterialShader or None, got {cls.shader!r}")
    if cls.emission_wgsl is not None and cls.record_radiance.__func__ is Material.record_radiance.__func__:
        raise TypeError(f"{where}: declares an emission but no record_radiance for the light table")
    if cls.emission_wgsl is not None and cls.emits is Material.emits:
        raise TypeError(f"{where}: declares an emission but does not say when it emits (`emits`)")


MATERIAL_KINDS = KindRegistry("material", _check_kind)
# every registered material kind in id order, and the class registered for a kind
material_classes = MATERIAL_KINDS.classes
material_class = MATERIAL_KINDS.lookup


@dataclass(eq=False)
class Material(Kind):
    """Materials compare by identity: two triangles share a material only if they share the object."""

    name: str

    registry: ClassVar[KindRegistry] = MATERIAL_KINDS
    parameter_error: ClassVar[type[ParameterError]] = MaterialError
    # the id the GPU switches on; trac0r's numbering for the first four (emitter 1 ... glossy 4)
    kind: ClassVar[int]
    # its BSDF code; None: it reflects nothing
    shader: ClassVar[MaterialShader | None] = None
    # every lobe is a delta (mirror, refraction): no light sample lands in one
    delta: ClassVar[bool] = False
    # WGSL bool over `material`: can a light sample land in the lobe, so that next-event estimation
    # pays at this vertex? None: no for a delta lobe, yes otherwise
    samples_lights: ClassVar[str | None] = None
    # the BSDF is the same seen from below (Mitsuba's `twosided`): `bsdf_sample` and friends mirror wi to +z first
    two_sided: ClassVar[bool] = True
    # a WGSL condition on the record that decides two-sidedness per material instead (Principled's)
    two_sided_wgsl: ClassVar[str | None] = None
    # WGSL vec3<f32> over `material`: the radiance it emits; None: it emits nothing
    emission_wgsl: ClassVar[str | None] = None
    # the parameter of `mitsuba_bsdf()` that its colour (the record's `color`, which vertex colours
    # multiply) fills, for the export of vertex-coloured triangles; None: not exported with them
    mitsuba_color: ClassVar[str | None] = None

    @property
    def label(self) -> str:
        return f"material {self.name!r}"

    def check_color(self, parameter: str, value, *, upper: float | None) -> tuple[float, float, float]:
        """An RGB triple (or one number for grey) of finite numbers >= 0, at most `upper` where energy
        must be conserved."""
        rgb = rgb_values(value)
        if rgb is None:
            raise MaterialError(f"{self.label}: {parameter} must be 3 numbers, got {value!r}", parameter)
        if not finite_non_negative(rgb):
            raise MaterialError(f"{self.label}: {parameter} must be finite and >= 0, got {value!r}", parameter)
        if upper is not None and np.any(rgb > upper):
            raise MaterialError(
                f"{self.label}: {parameter} must be <= {upper} (a reflectance above 1 creates energy), got {value!r}",
                parameter,
            )
        return (float(rgb[0]), float(rgb[1]), float(rgb[2]))

    @classmethod
    def light_sampling(cls) -> str:
        """`samples_lights`, or its default: WGSL "false" for a delta lobe, "true" otherwise."""
        if cls.samples_lights is not None:
            return cls.samples_lights
        return "false" if cls.delta else "true"

    @classmethod
    def record_radiance(cls, records: np.ndarray) -> np.ndarray:
        """(n, 3) float64: what `emission_wgsl` gives for MATERIAL `records` of this kind, as the light
        table weighs lights by it (`light_table`). Needed where `emission_wgsl` is set."""
        raise NotImplementedError(f"{cls.__name__} emits nothing")

    def fill_record(self, record: np.void) -> None:
        """Write the parameters into `record`, one MATERIAL record, by field name, as
        `shader` and `emission_wgsl` read them. `kind` is written by the caller; other fields stay zero."""
        raise NotImplementedError

    def lobes(self) -> frozenset[str]:
        """The optional lobes of its kind that it uses, whose code is compiled only into kernels of
        scenes that use them (`SceneFeatures.lobes`): none here."""
        return frozenset()

    def reads_tangent(self) -> bool:
        """Whether its BSDF is anisotropic: evaluated in a frame whose first axis is the surface's
        tangent (`surface_frame`), which its texture record's anisotropy_rotation turns. Never here."""
        return False

    def textures(self) -> dict[str, Texture]:
        """The textures it reads, by MATERIAL_TEXTURES slot ("base_color", "normal", ...): none here."""
        return {}

    def lets_rays_through(self) -> bool:
        """Whether rays pass through some of its surface (alpha modes, a single side), which every
        ray's triangle test then asks its texture record: never here."""
        return False

    def surface_emission(self) -> tuple[float, float, float]:
        """The radiance it emits through its texture record (times its "emission" texture where it
        has one), beside what an emitting kind emits (`emission_wgsl`): none here."""
        return (0.0, 0.0, 0.0)

    def emits(self) -> bool:
        """Whether it sends any light, through its kind's emission or its texture record."""
        return max(self.surface_emission()) > 0

    def absorption(self) -> tuple[float, float, float]:
        """sigma_a per channel (1 / scene units) of the light travelling inside it (`volume`): none here."""
        return (0.0, 0.0, 0.0)

    def fill_texture_record(self, record: np.void) -> None:
        """Write the parameters of its MATERIAL_TEXTURES record (the texture slots are the caller's):
        here opaque, seen from both sides, emitting nothing, its normals unscaled."""
        record["alpha"], record["alpha_mode"], record["alpha_cutoff"] = 1.0, ALPHA_MODES.index("OPAQUE"), 0.5
        record["double_sided"], record["emitted"], record["normal_scale"] = True, (0.0, 0.0, 0.0), 1.0
        record["anisotropy_rotation"] = 0.0

    def mitsuba_bsdf(self) -> dict:
        """The Mitsuba 3 BSDF dict of one side where `two_sided` (the exporter wraps it in `twosided`).
        Needed where `shader` is set."""
        raise NotImplementedError(f"{type(self).__name__} reflects nothing")

    def mitsuba_emitter(self) -> dict | None:
        """The Mitsuba 3 emitter dict of one side (the exporter adds the back); None: no emitter."""
        return None
