"""ReSTIR's direct light (Bitterli et al. 2020) at the first vertex of the path tracer's paths:
candidates from the light sampler resampled by their unshadowed contribution, combined with the
pixel's reservoir from its previous sample (kept in two pixel arrays), one shadow ray for the
survivor (shaders/integrators/restir/). The vertices after the first take their light as "mis"
does. Scenes that do not select it compile none of it."""

from __future__ import annotations

from ..gpu.bindings import STORAGE_READ_WRITE, Binding
from ..gpu.layout import RESERVOIR_RECEIVER, RESERVOIR_RECORD
from .integrator import PixelArray, register
from .path_tracer import path_tracer

# A pixel's reservoir and the surface point it was resampled for: two arrays, so that neither
# passes a device's largest storage binding before the other would (48 + 32 bytes a pixel).
RESERVOIRS = PixelArray(Binding("restir_reservoirs", STORAGE_READ_WRITE, RESERVOIR_RECORD), RESERVOIR_RECORD.size // 4)
RECEIVERS = PixelArray(
    Binding("restir_receivers", STORAGE_READ_WRITE, RESERVOIR_RECEIVER), RESERVOIR_RECEIVER.size // 4
)

RESTIR = register(
    path_tracer(
        "restir",
        "path tracing whose first vertex resamples light candidates by their contribution and reuses the "
        "pixel's reservoir from its previous sample (ReSTIR), MIS after it",
        "mis",
        first_vertex_light="integrators/restir/resampled_direct_light.wgsl",
        pixel_arrays=(RESERVOIRS, RECEIVERS),
    )
)
