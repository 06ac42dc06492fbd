"""The moving picture's upscale factor as a function of the measured costs and the budget
(`choose_upscale`): the smallest factor whose frame fits, unmeasured factors estimated from the
nearest measured one, FIRST_FACTOR before any measurement; where none fits, the finest within
OVER_BUDGET_SLACK of the cheapest."""

from __future__ import annotations

import pytest

from wgputrace.view.upscale_choice import (
    COARSER_AFTER_FRAMES,
    FINER_MARGIN,
    FIRST_FACTOR,
    KEEP_MARGIN,
    OVER_BUDGET_SLACK,
    FrameCost,
    choose_upscale,
    estimated_cost,
    usable_factors,
)

SIZE = (320, 240)
# at 8x: 10 ms of tracing one sample of 1/64 of the pixels, 20 ms for the rest of the frame
COARSE = {8: FrameCost(0.010, 0.020)}


def test_before_any_measurement_the_first_frame_is_the_middle_factor():
    assert choose_upscale({}, 1.0, SIZE) == FIRST_FACTOR == 4
    assert choose_upscale({}, 1.0, (3, 3)) == 2  # a 4 x 4 block does not fit a 3 x 3 image


def test_an_unmeasured_factor_scales_the_nearest_measured_ones_tracing_by_the_pixels_traced():
    # 8x -> 1x traces 64 times the pixels; the rest of the frame stays
    assert estimated_cost(COARSE, 1) == pytest.approx(0.020 + 64 * 0.010)
    assert estimated_cost(COARSE, 4) == pytest.approx(0.020 + 4 * 0.010)
    costs = {**COARSE, 2: FrameCost(0.100, 0.030)}
    assert estimated_cost(costs, 4) == pytest.approx(0.030 + 0.100 / 4)  # 2x is as near as 8x: the finer
    assert estimated_cost(costs, 1) == pytest.approx(0.030 + 4 * 0.100)
    assert estimated_cost(costs, 2) == pytest.approx(0.130)  # measured


@pytest.mark.parametrize(
    "budget, expected",
    [
        (0.020 + 64 * 0.010, 1),  # a full pass fits exactly
        (0.020 + 64 * 0.010 - 1e-6, 2),
        (0.020 + 16 * 0.010, 2),
        (0.020 + 4 * 0.010, 4),
        (0.030, 8),  # only the measured coarsest fits
        (0.001, 8),  # nothing fits, and the finer factors cost far more than the coarsest
    ],
)
def test_the_smallest_factor_whose_frame_fits_the_budget(budget, expected):
    assert choose_upscale(COARSE, budget, SIZE) == expected


def test_where_nothing_fits_a_finer_factor_within_the_slack_is_taken():
    # the rest of the frame outweighs tracing, as on lavapipe: 4x costs 1.1 times 8x's, 2x 1.5 times
    rest_heavy = {8: FrameCost(0.002, 0.058)}
    assert estimated_cost(rest_heavy, 4) <= (1 + OVER_BUDGET_SLACK) * estimated_cost(rest_heavy, 8)
    assert choose_upscale(rest_heavy, 0.050, SIZE) == 4
    # from 8x (kept up to KEEP_MARGIN of the budget) once 8x no longer fits either
    assert choose_upscale(rest_heavy, 0.060 / KEEP_MARGIN - 1e-6, SIZE, current=8) == 4
    # a little dearer tracing and 4x is no longer within the slack
    assert choose_upscale({8: FrameCost(0.004, 0.058)}, 0.050, SIZE) == 8


def test_the_current_factor_is_kept_while_it_fits_the_keep_margin():
    # 4x costs 0.060, 8x 0.030: at a budget of 0.050 only 8x fits, but 4x is kept up to 0.0625
    costs = {4: FrameCost(0.040, 0.020), 8: FrameCost(0.010, 0.020)}
    assert choose_upscale(costs, 0.050, SIZE) == 8
    assert choose_upscale(costs, 0.060 / KEEP_MARGIN, SIZE, current=4) == 4
    assert choose_upscale(costs, 0.060 / KEEP_MARGIN - 1e-6, SIZE, current=4) == 8


def test_a_coarser_factor_only_after_a_moving_historys_length_at_the_current_one():
    costs = {4: FrameCost(0.040, 0.020), 8: FrameCost(0.010, 0.020)}
    assert choose_upscale(costs, 0.040, SIZE, current=4, frames_at_current=COARSER_AFTER_FRAMES) == 8
    assert choose_upscale(costs, 0.040, SIZE, current=4, frames_at_current=COARSER_AFTER_FRAMES - 1) == 4
    # a finer one at once
    assert choose_upscale(costs, 1.0, SIZE, current=8, frames_at_current=1) == 1


def test_a_finer_factor_than_the_current_one_must_fit_within_the_margin():
    at_two = 0.020 + 16 * 0.010
    assert choose_upscale(COARSE, at_two, SIZE, current=8) == 4
    assert choose_upscale(COARSE, at_two / FINER_MARGIN, SIZE, current=8) == 2
    # a coarser or the same factor needs only the budget
    assert choose_upscale(COARSE, at_two, SIZE, current=2) == 2
    assert choose_upscale(COARSE, at_two, SIZE, current=1) == 2


def test_a_measured_cost_over_the_budget_keeps_the_factor_coarser():
    costs = {**COARSE, 1: FrameCost(0.5, 0.1)}  # measured dearer than 8x's estimate of it
    assert choose_upscale(costs, 0.4, SIZE) == 2


def test_small_images_take_only_the_factors_whose_block_fits():
    assert usable_factors((3, 100)) == (1, 2)
    assert choose_upscale({2: FrameCost(1.0, 1.0)}, 0.001, (3, 100)) == 2


def test_smoothing_moves_a_cost_a_tenth_of_the_way():
    cost = FrameCost(0.010, 0.020).smoothed(FrameCost(0.020, 0.040))
    assert cost.trace == pytest.approx(0.011) and cost.rest == pytest.approx(0.022)
