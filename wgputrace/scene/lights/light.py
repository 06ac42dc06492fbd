"""The base of every light kind that is not an emissive triangle, and the registry of those kinds.

A light kind is one class in one module of this package plus its WGSL file, and nothing else: like
a material kind (`Material`) the class is the whole descriptor, and like pbrt-v4's `Light` it
answers what the light sampler and the integrator ask.

| what                                      | on the class             | driven from it                                   |
|-------------------------------------------|--------------------------|--------------------------------------------------|
| the id the GPU switches on                | `kind`                   | `LIGHT_<NAME>` constants, the records' kind      |
| parameters and their checks               | dataclass fields, `checked_placement` | editing re-checks (`__setattr__`) |
| the parameter that scales `color`         | `strength`               | its check, `rgb_strength`                        |
| its GPU record                            | `fill_record`            | `SceneMirror`'s light source records             |
| its sampling code (and what escaped rays see) | `shader`             | `light_dispatch`: generated dispatch             |
| where its light paths start               | `shader.emission_sample` | `light_emission_dispatch` (bidirectional paths)  |
| a delta light (only light sampling finds it)? | `delta`              | `HAS_DELTA_LIGHTS`: weight 1, under every integrator |
| infinitely far (shadow rays to infinity)? | `distant`                | its LightSample, the power estimate              |
| its share of the light sampler            | `weight`                 | `light_table`'s alias table                      |
| its Mitsuba 3 equivalent                  | `mitsuba_emitter`        | `mitsuba_scene`                                  |

Directions (`direction`) are the way the light TRAVELS (Mitsuba's `directional` and `spot`, glTF's
-Z), normalised when set. Assigning a parameter re-runs the light's checks (LightError names the
light, the parameter and the value, and leaves the light as it was) and bumps `version`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..registry import Kind, KindRegistry, ParameterError, finite_non_negative, rgb_values

# Rec. 709 luminance, the weights of the light sampler (`light_table`) and the shaders.
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])
# As the Emitter material's RADIANCE_MAX: far above any physical source, low enough that the
# float32 sums of billions of samples per pixel stay finite.
INTENSITY_MAX = 1e20


class LightError(ParameterError):
    """A light parameter is out of its documented range; `parameter` names it."""


@dataclass(frozen=True)
class LightShader:
    """A kind's WGSL: its file under shaders/ and the calls the generated dispatch makes into it.
    `sample` sees `light` (its LightSource record), `p` (the receiving point) and `u` (vec2) and
    returns a LightSample; a distant light that is not a delta (the sun) also gives what a ray
    escaping along `direction` sees of it, `escaped_radiance` (vec3) and `escaped_pdf` (the density
    per steradian with which `sample` draws `direction`, before the light's selection probability).
    Light paths: `emission_sample` sees `light`, `disk` (the scene's SceneDisk), `u_position` and
    `u_direction` (vec2) and returns an EmissionSample, its densities before the selection
    probability; a light at a finite distance also gives `emission_pdf`, its EmissionPdf for sending
    `direction`. Distant lights' densities are their mixture's (`distant_emission`).
    """

    file: str
    sample: str
    escaped_radiance: str | None = None
    escaped_pdf: str | None = None
    emission_sample: str = ""
    emission_pdf: str | None = None


def luminance(rgb) -> float:
    return float(np.asarray(rgb, np.float64) @ LUMINANCE_WEIGHTS)


def _check_kind(cls: type[Light], where: str) -> None:
    if not isinstance(cls.shader, LightShader):
        raise TypeError(f"{where}: shader must be a LightShader, got {cls.shader!r}")
    if cls.distant and not cls.delta and cls.shader.escaped_radiance is None:
        raise TypeError(f"{where}: a distant light that is not a delta must say what escaped rays see of it")
    if not cls.shader.emission_sample:
        raise TypeError(f"{where}: its shader must give emission_sample, where light paths start")
    if not cls.distant and cls.shader.emission_pdf is None:
        raise TypeError(f"{where}: a light at a finite distance must give emission_pdf beside emission_sample")


LIGHT_KINDS = KindRegistry("light", _check_kind)
# every registered light kind in id order, and the class registered for a kind
light_classes = LIGHT_KINDS.classes
light_class = LIGHT_KINDS.lookup


@dataclass(eq=False)
class Light(Kind):
    """Lights compare by identity, as materials do."""

    registry: ClassVar[KindRegistry] = LIGHT_KINDS
    parameter_error: ClassVar[type[ParameterError]] = LightError
    # the id the GPU switches on
    kind: ClassVar[int]
    shader: ClassVar[LightShader]
    # a point or a single direction: no BSDF sample can hit it, only light sampling reaches it
    delta: ClassVar[bool] = False
    # infinitely far: its shadow rays run to infinity and its power is what crosses the scene
    distant: ClassVar[bool] = False
    # the parameter that scales its `color` field: "intensity" (W/sr) or "irradiance" (W/m^2), which
    # checked_parameters checks with check_strength (a kind with its own checked_parameters may have none)
    strength: ClassVar[str]

    @property
    def label(self) -> str:
        """How errors name the light: its class, and its name where it has one."""
        name = getattr(self, "name", None)
        return type(self).__name__ + (f" {name!r}" if name else "")

    def checked_parameters(self) -> dict[str, object]:
        color = self.check_color("color", self.color)
        checked = self.checked_placement()
        checked[self.strength] = self.check_strength(self.strength, getattr(self, self.strength), color)
        checked["color"] = color
        return checked

    def checked_placement(self) -> dict[str, object]:
        """The kind's parameters besides `color` and its strength (where it is, which way it points, its
        angles), checked and normalised after color and before the strength."""
        raise NotImplementedError

    @property
    def rgb_strength(self) -> tuple[float, float, float]:
        """color x the strength: the RGB intensity or irradiance."""
        return scaled(self.color, getattr(self, self.strength))

    def fill_record(self, record: np.void) -> None:
        """Write the parameters into `record`, one LIGHT_SOURCE record, by field name,
        as `shader` reads them. `kind` and `probability` are written by the caller."""
        raise NotImplementedError

    def weight(self, scene_radius: float) -> float:
        """The light sampler's weight: the estimated emitted power (of the luminance) over 2 pi, the
        unit in which a two-sided emissive triangle, emitting 2 pi x area x luminance, weighs its
        area x luminance (`light_table`). A distant light's power is what it sends through a
        disc of the scene's bounding radius `scene_radius`."""
        raise NotImplementedError

    def mitsuba_emitter(self) -> dict | None:
        """The Mitsuba 3 emitter dict; None where no Mitsuba plugin is this light. A transform is
        given as {"look_at": {"origin", "target", "up"}}, which the exporter turns into Mitsuba's
        `ScalarTransform4f().look_at`."""
        raise NotImplementedError

    # the checks every kind shares

    def check_vector(self, parameter: str, value, *, unit: bool) -> tuple[float, float, float]:
        """3 finite numbers; normalised (and not zero) where `unit`."""
        try:
            vector = np.asarray(value, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            vector = np.zeros(0)
        if vector.size != 3 or not np.all(np.isfinite(vector)):
            raise LightError(f"{self.label}: {parameter} must be 3 finite numbers, got {value!r}", parameter)
        if unit:
            length = float(np.linalg.norm(vector))
            if not length > 0.0:
                raise LightError(f"{self.label}: {parameter} must not be zero, got {value!r}", parameter)
            vector = vector / length
        return (float(vector[0]), float(vector[1]), float(vector[2]))

    def check_color(self, parameter: str, value) -> tuple[float, float, float]:
        """An RGB triple (or one number for grey) of finite numbers >= 0."""
        rgb = rgb_values(value)
        if rgb is None or not finite_non_negative(rgb):
            raise LightError(f"{self.label}: {parameter} must be 3 finite numbers >= 0, got {value!r}", parameter)
        return (float(rgb[0]), float(rgb[1]), float(rgb[2]))

    def check_strength(self, parameter: str, value, color: tuple[float, float, float]) -> float:
        """An intensity or irradiance: finite, >= 0, and with its colour at most INTENSITY_MAX."""
        strength = self.check_number(parameter, value, low=0, high=INTENSITY_MAX)
        if max(color) * strength > INTENSITY_MAX:
            raise LightError(
                f"{self.label}: {parameter} x color = {max(color) * strength:.3g} exceeds INTENSITY_MAX = "
                f"{INTENSITY_MAX:g} ({parameter} {strength}, color {color})",
                parameter,
            )
        return strength


def scaled(color, strength: float) -> tuple[float, float, float]:
    return tuple(float(c) * strength for c in color)
