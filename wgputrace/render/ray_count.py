"""Count what a render does: the rays it traces and how busy the lanes that run in lockstep are in
its loops, with the renderer's own kernel compiled with counters (`ray_count_hook`).

Renders are deterministic (same seed, same adapter, same arguments: the same image bit for bit),
so counting the samples a timed render took, from the same random state, counts exactly that
render's rays; the timed kernel itself never carries a counter. The counted samples go into the
renderer's accumulation like any others, in the same dispatches as `render` makes, so the caller
can check that the counted image equals the timed one bit for bit: the proof that the counts
belong to those paths.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..gpu.buffers import read_buffer, storage_buffer, write_buffer
from ..kernels.compile import tracing_kernel
from ..kernels.ray_count import COUNTER_SLOTS, LANE_LOOPS, RAY_KINDS
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


@dataclass(frozen=True)
class LaneCounts:
    """How busy the lanes were in each counted loop (LANE_LOOPS) of `samples_per_pixel` samples of
    every pixel: `passes` of a subgroup through the loop and the `lanes` active in them."""

    pixels: int
    samples_per_pixel: int
    passes: dict[str, int]
    lanes: dict[str, int]

    @property
    def subgroup_size(self) -> float:
        """Lanes per subgroup: every lane is active where the kernel starts."""
        return self.lanes["invocation"] / self.passes["invocation"]

    def utilisation(self, loop: str) -> float:
        """Active lanes per pass through `loop` over the subgroup size (1: no lane ever idle)."""
        return self.lanes[loop] / (self.passes[loop] * self.subgroup_size)

    def passes_per_sample(self, loop: str) -> float:
        """Passes through `loop` per subgroup and sample: what the subgroup's time follows."""
        subgroups = self.pixels * self.samples_per_pixel / self.subgroup_size
        return self.passes[loop] / subgroups


def _counted(renderer: Renderer, spp: int, **counters: bool) -> np.ndarray:
    """Add `spp` samples per pixel to `renderer` as `render(spp)` would, through its kernel with
    `counters` on; the counter slots summed over the dispatches, read back after each so that
    32-bit atomics cannot wrap within a run."""
    if spp < 1:
        raise ValueError(f"spp must be >= 1, got {spp}")
    renderer.update()
    context = renderer.context
    kernel = tracing_kernel(context, replace(renderer.variant, **counters))
    zeros = np.zeros(COUNTER_SLOTS, np.uint32)
    counter = storage_buffer(context, "counts", zeros, read_back=True)
    group = {"ray_count": kernel.bind("ray_count", ray_counts=counter)}
    totals = np.zeros(COUNTER_SLOTS, np.uint64)
    for samples in renderer.dispatch_sizes(spp):
        write_buffer(context, counter, 0, zeros)
        renderer.dispatch(samples, kernel, group)
        totals += read_buffer(context, counter, np.uint32, COUNTER_SLOTS)
    renderer.stats.samples_per_pixel += spp
    return totals


def count_rays(renderer: Renderer, spp: int) -> RayCounts:
    """Add `spp` samples per pixel to `renderer` as `render(spp)` would, counting their rays."""
    totals = _counted(renderer, spp, count_rays=True)
    counts = dict(zip(RAY_KINDS, (int(total) for total in totals), strict=False))
    return RayCounts(renderer.width * renderer.height, spp, **counts)


def count_lanes(renderer: Renderer, spp: int) -> LaneCounts:
    """Add `spp` samples per pixel to `renderer` as `render(spp)` would, counting the lanes active
    in each pass through its loops (an adapter with subgroup operations: `has_subgroups`)."""
    if not renderer.context.has_subgroups:
        raise ValueError(f"{renderer.context.adapter_name} has no subgroup operations to count lanes with")
    slots = _counted(renderer, spp, count_lanes=True)[len(RAY_KINDS) :].reshape(len(LANE_LOOPS), 2)
    passes = {loop: int(slot[0]) for loop, slot in zip(LANE_LOOPS, slots, strict=True)}
    lanes = {loop: int(slot[1]) for loop, slot in zip(LANE_LOOPS, slots, strict=True)}
    return LaneCounts(renderer.width * renderer.height, spp, passes, lanes)
