"""Count the rays a render traces: the renderer's own path tracer with ray counters compiled in.

Renders are deterministic (same seed, same adapter, same arguments: the same image bit for bit),
so counting the samples a timed render took, from the same random state, counts exactly that
render's rays; the timed kernel itself never carries a counter (`ray_count_hook`). The counted
samples go into the renderer's accumulation like any others, so the caller can check that the
counted image equals the timed one bit for bit: the proof that the count belongs to those paths.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..gpu.buffers import read_buffer, storage_buffer, write_buffer
from ..kernels.compile import tracing_kernel
from ..kernels.ray_count import RAY_KINDS
from .renderer import Renderer


@dataclass(frozen=True)
class RayCounts:
    """Rays traced by `samples_per_pixel` samples of every pixel."""

    pixels: int
    samples_per_pixel: int
    closest_hit: int  # camera rays and extension rays: every ray that looks for the nearest surface
    shadow: int  # light samples' occlusion tests

    @property
    def camera(self) -> int:
        """One camera ray starts every path."""
        return self.pixels * self.samples_per_pixel

    @property
    def extension(self) -> int:
        """Rays that continue a path after a bounce."""
        return self.closest_hit - self.camera

    @property
    def total(self) -> int:
        return self.closest_hit + self.shadow


def count_rays(renderer: Renderer, spp: int) -> RayCounts:
    """Add `spp` samples per pixel to `renderer` as `render(spp)` would, counting their rays.

    Counters are read back after every sample, so 32-bit atomics cannot wrap within a run.
    """
    if spp < 1:
        raise ValueError(f"spp must be >= 1, got {spp}")
    renderer.update()
    context = renderer.context
    kernel = tracing_kernel(context, replace(renderer.variant, count_rays=True))
    zeros = np.zeros(len(RAY_KINDS), np.uint32)
    counter = storage_buffer(context, "ray counts", zeros, read_back=True)
    bind_groups = {**renderer.bind_groups, "ray_count": kernel.bind("ray_count", ray_counts=counter)}
    totals = np.zeros(len(RAY_KINDS), np.uint64)
    for _ in range(spp):
        write_buffer(context, counter, 0, zeros)
        kernel.dispatch((renderer.width, renderer.height), bind_groups)
        totals += read_buffer(context, counter, np.uint32, len(RAY_KINDS))
    renderer.stats.samples_per_pixel += spp
    counts = dict(zip(RAY_KINDS, (int(total) for total in totals), strict=True))
    return RayCounts(renderer.width * renderer.height, spp, **counts)
