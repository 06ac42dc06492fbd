"""Which upscale factor the moving picture traces at (`TemporalPicture`): the smallest of 1 and
UPSCALE_FACTORS whose one frame fits the trace budget, from each factor's measured cost.

A frame's cost has two parts, measured apart: tracing one sample per traced pixel (a quarter as
many pixels at each doubling of the factor) and the rest (rebuilding, filtering, reading back
and uploading the full picture, about the same at every factor). A factor not measured yet is
estimated from the nearest measured one: its rest, and its tracing scaled by the traced pixels.
Before anything is measured the first frame starts at FIRST_FACTOR. Where no factor fits, the
frame is late whichever is taken, and the rest of the frame, not the tracing, is what makes it
late: the finest factor within OVER_BUDGET_SLACK of the cheapest one's cost is taken, rather than
the cheapest, whose picture is the worst. Each change of factor starts the history again, so the
current factor is kept within KEEP_MARGIN of the budget and left for a coarser one only after
COARSER_AFTER_FRAMES frames."""

from __future__ import annotations

from dataclasses import dataclass

from ..render.temporal_accumulation import MOVING_HISTORY_FRAMES
from ..render.temporal_upsampling import UPSCALE_FACTORS

# Every factor the moving picture may take, finest first (1: every pixel each frame).
FACTORS = (1, *UPSCALE_FACTORS)
# A finer factor than the current one is taken only where its frame fits this part of the budget:
# each switch starts the history again (`Renderer.render_frame`), so costs measured near the
# budget must not flip the factor back and forth.
FINER_MARGIN = 0.8
# The factor of the last frame is kept while its frame fits this part of the budget, for the same
# reason: in bench.realtime's Cornell fly-through at 320x240 a 4x frame took 45-70 ms and an 8x one
# a little less, against a 50 ms budget, and without it the factor flipped between the two four
# times in 60 frames, each flip starting the history again (instability 0.091 against 0.070).
KEEP_MARGIN = 1.25
# A coarser factor is taken only after this many frames at the current one: a frame's cost on a
# loaded CPU wanders by half, and with KEEP_MARGIN alone bench.realtime's moving-objects fly-through
# still went between 4x and 8x four times in its first 20 frames. It is a moving history's length,
# which no switch sooner lets fill. A finer factor is taken at once.
COARSER_AFTER_FRAMES = MOVING_HISTORY_FRAMES
# Where no factor fits the budget, a finer factor is taken if its frame costs at most this part
# more than the cheapest's. On lavapipe at 320x240 the rest of the frame (rebuilding, filtering)
# outweighs tracing: an 8x frame measured 2.3-2.7 ms of tracing and about 70 ms in all, so a 4x
# frame is estimated 1.13-1.15 times as dear before it is measured (an upper bound) and measures
# about 1.05; its fly-throughs' mean FLIP is 0.194 against 0.229 (Cornell box) and 0.120 against
# 0.170 (asset; bench.realtime, 30 frames).
OVER_BUDGET_SLACK = 0.15
# The factor of the first frame, before anything is measured: the middle one. An estimate from a
# coarser factor over-counts a finer one's tracing (a small dispatch costs more per pixel) and one
# from a finer factor under-counts a coarser one's, so the middle reaches both ways: a fast adapter
# goes finer at once, and where the rest of the frame outweighs tracing (lavapipe) 4x stays within
# OVER_BUDGET_SLACK of 8x's estimate. Started at 8x, bench.realtime's Cornell box stayed at 8x on
# every frame (4x estimated from it beyond the slack) at FLIP 0.235 in its first 20 frames.
FIRST_FACTOR = 4
# A new measurement of a factor's cost moves its estimate by this fraction (as FramePacing smooths
# the cost besides tracing).
COST_SMOOTHING = 0.1


@dataclass(frozen=True)
class FrameCost:
    """The measured seconds of one frame at a factor: tracing one sample of its pixels, and the rest."""

    trace: float
    rest: float

    @property
    def total(self) -> float:
        return self.trace + self.rest

    def smoothed(self, new: FrameCost) -> FrameCost:
        """This cost moved by COST_SMOOTHING towards `new`."""
        return FrameCost(
            self.trace + COST_SMOOTHING * (new.trace - self.trace), self.rest + COST_SMOOTHING * (new.rest - self.rest)
        )


def usable_factors(size: tuple[int, int]) -> tuple[int, ...]:
    """The factors an image of `size` (width, height) takes: those whose block fits in it."""
    return tuple(factor for factor in FACTORS if factor <= min(size))


def estimated_cost(costs: dict[int, FrameCost], factor: int) -> float:
    """The seconds of one frame at `factor`: measured, or from the nearest measured factor (the
    finer one on a tie), its tracing scaled by the pixels traced. `costs` must not be empty."""
    if factor in costs:
        return costs[factor].total
    nearest = min(costs, key=lambda measured: (abs(measured.bit_length() - factor.bit_length()), measured))
    cost = costs[nearest]
    return cost.rest + cost.trace * (nearest / factor) ** 2


def _margin(factor: int, current: int | None) -> float:
    """The part of the budget `factor`'s frame must fit, the last frame's factor being `current`."""
    if current is None:
        return 1.0
    if factor < current:
        return FINER_MARGIN
    return KEEP_MARGIN if factor == current else 1.0


def choose_upscale(
    costs: dict[int, FrameCost],
    budget: float,
    size: tuple[int, int],
    current: int | None = None,
    frames_at_current: int = COARSER_AFTER_FRAMES,
) -> int:
    """The factor of the next frame of an image of `size` with `budget` seconds to trace it: the
    smallest usable one whose cost (`estimated_cost`) fits the budget, or FINER_MARGIN of it where
    it is finer than `current` (the last frame's), or KEEP_MARGIN of it where it is `current`;
    FIRST_FACTOR (or the coarsest usable one below it) where none is measured; where none fits,
    the smallest whose cost is within OVER_BUDGET_SLACK of the cheapest's. A factor coarser than
    `current` only once `frames_at_current` (frames at it in a row) reach COARSER_AFTER_FRAMES."""
    factors = usable_factors(size)
    if not costs:
        return min(FIRST_FACTOR, factors[-1])
    if current is not None and frames_at_current < COARSER_AFTER_FRAMES:
        factors = tuple(factor for factor in factors if factor <= current)
    estimates = {factor: estimated_cost(costs, factor) for factor in factors}
    for factor in factors:
        if estimates[factor] <= budget * _margin(factor, current):
            return factor
    cheapest = min(estimates.values())
    return next(factor for factor in factors if estimates[factor] <= cheapest * (1.0 + OVER_BUDGET_SLACK))
