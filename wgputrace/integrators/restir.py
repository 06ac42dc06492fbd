"""ReSTIR's direct light (Bitterli et al. 2020) at the first vertex of the path tracer's paths:
candidates from the light sampler resampled by their unshadowed contribution, one shadow ray for
the survivor (shaders/integrators/resampled_direct_light.wgsl). The vertices after the first take
their light as "mis" does. Scenes that do not select it compile none of it."""

from __future__ import annotations

from .integrator import register
from .path_tracer import path_tracer

RESTIR = register(
    path_tracer(
        "restir",
        "path tracing whose first vertex resamples light candidates by their contribution (ReSTIR's RIS), MIS after it",
        "mis",
        first_vertex_light="integrators/resampled_direct_light.wgsl",
    )
)
