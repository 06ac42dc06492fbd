"""Which upscale factor the moving picture traces at (`TemporalPicture`): the smallest of 1 and
UPSCALE_FACTORS whose one frame fits the trace budget, from each factor's measured cost.

A frame's cost has two parts, measured apart: tracing one sample per traced pixel (a quarter as
many pixels at each doubling of the factor) and the rest (rebuilding, filtering, reading back
and uploading the full picture, about the same at every factor). A factor not measured yet is
estimated from the nearest measured one: its rest, and its tracing scaled by the traced pixels.
Before anything is measured the first frame starts at the coarsest factor, as the reset preview
started at its coarsest size."""

from __future__ import annotations

from dataclasses import dataclass

from ..render.temporal_upsampling import UPSCALE_FACTORS

# Every factor the moving picture may take, finest first (1: every pixel each frame).
FACTORS = (1, *UPSCALE_FACTORS)
# A finer factor than the current one is taken only where its frame fits this part of the budget:
# each switch starts the history again (`Renderer.render_frame`), so costs measured near the
# budget must not flip the factor back and forth.
FINER_MARGIN = 0.8
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


def choose_upscale(
    costs: dict[int, FrameCost], budget: float, size: tuple[int, int], current: int | None = None
) -> int:
    """The factor of the next frame of an image of `size` with `budget` seconds to trace it: the
    smallest usable one whose cost (`estimated_cost`) fits the budget, or FINER_MARGIN of it where
    it is finer than `current` (the last frame's); the coarsest where none fits or none is measured."""
    factors = usable_factors(size)
    if not costs:
        return factors[-1]
    for factor in factors:
        allowed = budget * (FINER_MARGIN if current is not None and factor < current else 1.0)
        if estimated_cost(costs, factor) <= allowed:
            return factor
    return factors[-1]
