"""Absorption inside transmissive materials (glTF's KHR_materials_volume): Beer-Lambert attenuation
of the light that travels through a mesh, given as glTF gives it.

| parameter            | type          | default  | meaning                                                        |
|----------------------|---------------|----------|----------------------------------------------------------------|
| attenuation_color    | RGB in [0, 1] | 1        | the colour white light turns after attenuation_distance inside |
| attenuation_distance | float > 0     | infinity | the distance, in scene units, at which it has that colour      |

Light crossing a distance d inside is multiplied by attenuation_color^(d / attenuation_distance):
the absorption coefficient is sigma_a = -ln(attenuation_color) / attenuation_distance per channel
(`absorption_coefficients`). A path tracer traces the real distance, so glTF's thicknessFactor
(a rasteriser's guess of it) is not needed. A path segment is inside a material when it ends on the
material's back face (the side its normal points away from): a closed mesh with nothing inside it.
Objects or lights inside an absorbing mesh, and meshes nested in one another, are not supported
(the medium of a segment is the material of the surface it ends on, seen from behind); nor are
open meshes, whose back may be seen from outside.

Next-event estimation needs nothing more: shadow rays stop at every surface, dielectrics included,
so one that reaches its light never ran inside a closed mesh with no light in it. The path
tracers (`segment_transmittance` in their kernels) trace absorption; bdpt refuses an absorbing
material by name (`Integrator.check_materials`).
"""

from __future__ import annotations

import math

import numpy as np

from ..registry import mitsuba_rgb
from .material import Material, MaterialError

# sigma_a of a channel whose attenuation_color is 0 (all its light absorbed at once): finite, so
# that sigma_a x t is never inf x 0 = NaN on the GPU, and so large that exp(-sigma_a x t) is 0 for
# every distance above float32's smallest normal lengths.
ABSORPTION_MAX = 1e30
# Mitsuba 3.9's volpath returns NaN through a medium with a channel of sigma_t exactly 0 (an
# attenuation_color of 1 in one channel); that channel is exported as this fraction of the largest,
# which absorbs less than float32 can show over any distance in the scene.
MITSUBA_SIGMA_MIN_RELATIVE = 1e-9


def absorption_coefficients(attenuation_color, attenuation_distance: float) -> tuple[float, float, float]:
    """sigma_a per channel (1 / scene units) for glTF's attenuation colour and distance; a colour 0
    channel gives ABSORPTION_MAX, an infinite distance none."""
    color = np.asarray(attenuation_color, np.float64)
    with np.errstate(divide="ignore"):
        sigma = -np.log(color) / attenuation_distance
    sigma = np.minimum(np.where(color > 0.0, sigma, ABSORPTION_MAX), ABSORPTION_MAX)
    return tuple(float(s) + 0.0 for s in sigma)  # + 0.0: -0.0 where the colour is 1


def checked_attenuation(material: Material, color, distance) -> dict[str, object]:
    """The two parameters validated and normalised, or MaterialError naming the material and the
    first bad one."""
    checked_color = material.check_color("attenuation_color", color, upper=1.0)
    message = f"{material.label}: attenuation_distance must be > 0 (inf: no absorption), got {distance!r}"
    try:
        checked_distance = float(distance)
    except (TypeError, ValueError):
        raise MaterialError(message, "attenuation_distance") from None
    if math.isnan(checked_distance) or checked_distance <= 0.0:
        raise MaterialError(message, "attenuation_distance")
    return {"attenuation_color": checked_color, "attenuation_distance": checked_distance}


def mitsuba_medium(absorption) -> dict | None:
    """Mitsuba 3's interior medium for `absorption` (sigma_a per channel): `homogeneous`, albedo 0
    (it absorbs only) and sigma_t = sigma_a, given as an RGB in [0, 1] (how Mitsuba reads it)
    times its `scale`, at least MITSUBA_SIGMA_MIN_RELATIVE of it; None for no absorption."""
    largest = max(absorption)
    if largest <= 0.0:
        return None
    return {
        "type": "homogeneous",
        "albedo": 0.0,
        "sigma_t": mitsuba_rgb([max(s / largest, MITSUBA_SIGMA_MIN_RELATIVE) for s in absorption]),
        "scale": largest,
    }


def is_absorbing(material: Material) -> bool:
    """Whether light inside `material` is absorbed (`Material.absorption`)."""
    return max(material.absorption()) > 0.0
