"""Rendering to a time budget (`render(seconds=...)`) and until `stop()`: how submits are sized
(SubmitPlan, with made-up timings), then on the GPU what the budget promises without asserting
wall-clock figures: at least one sample, no submit started after the deadline, the cap kept."""

from __future__ import annotations

import math
import time

import pytest

import wgputrace as wt
from wgputrace.render.renderer import _MAX_SAMPLES_PER_SUBMIT, _TARGET_SUBMIT_SECONDS, SubmitPlan

SIZE = 16
ENDLESS_SPP = 1_000_000


def test_submits_double_while_quick_and_keep_to_what_is_left():
    plan = SubmitPlan()
    sizes = []
    for _ in range(10):
        sizes.append(plan.next())
        plan.measured(sizes[-1], 0.01 * _TARGET_SUBMIT_SECONDS)
    assert sizes == [1, 2, 4, 8, 16, 32, 64, 64, 64, 64] and _MAX_SAMPLES_PER_SUBMIT == 64
    assert plan.next(left=5) == 5
    plan.measured(64, _TARGET_SUBMIT_SECONDS)  # a slow submit: no more growth
    assert plan.next() == 64


def test_after_one_sample_submits_take_whole_dispatches_and_grow_to_the_cap():
    plan = SubmitPlan(8)
    sizes = []
    for _ in range(6):
        sizes.append(plan.next())
        plan.measured(sizes[-1], 0.01 * _TARGET_SUBMIT_SECONDS)
    assert sizes == [1, 8, 16, 32, 64, 64]
    assert plan.next(left=5) == 5  # the render's last dispatch takes fewer
    slow = SubmitPlan(100)
    slow.measured(slow.next(), 10 * _TARGET_SUBMIT_SECONDS)
    assert slow.next() == 100  # a dispatch is never cut below what it takes, however slow


def test_a_budget_shrinks_the_submit_to_the_time_remaining():
    plan = SubmitPlan()
    assert plan.next(remaining_seconds=1e-9) == 1  # nothing measured yet: one dispatch to measure
    plan.samples = 32
    plan.measured(32, 32 * 0.01)  # 10 ms per sample
    assert plan.next(remaining_seconds=0.125) == 12
    assert plan.next(left=3, remaining_seconds=0.125) == 3
    assert plan.next(remaining_seconds=0.005) == 0  # not one more fits
    assert plan.next(remaining_seconds=-1.0) == 0


def test_render_needs_an_end_and_a_positive_budget(gpu_context):
    renderer = wt.Renderer(wt.load_scene("cornell"), SIZE, SIZE)
    with pytest.raises(ValueError, match="spp, seconds or stop"):
        renderer.render()
    for seconds in (0, -1.0, math.nan):
        with pytest.raises(ValueError, match="seconds must be > 0"):
            renderer.render(seconds=seconds)
    assert renderer.samples_per_pixel == 0


def test_a_tiny_budget_still_renders_one_sample(gpu_context):
    renderer = wt.Renderer(wt.load_scene("cornell"), SIZE, SIZE)
    renderer.render(8)  # submits have grown and the time per dispatch is known
    renderer.render(seconds=1e-9)
    assert renderer.samples_per_pixel == 9


def test_a_budget_stops_before_the_cap_and_starts_no_submit_after_the_deadline(gpu_context):
    seconds = 0.5
    renderer = wt.Renderer(wt.load_scene("cornell"), SIZE, SIZE)
    finished = []  # when each submit's samples were counted
    start = time.perf_counter()
    renderer.render(ENDLESS_SPP, lambda samples: finished.append(time.perf_counter()), seconds=seconds)
    assert 1 <= renderer.samples_per_pixel < ENDLESS_SPP
    # a submit starts right after the previous one's progress call: all but the last began in time,
    # and the last one was sized to the time then remaining (SubmitPlan, tested above)
    assert all(moment - start < seconds for moment in finished[:-1])


def test_spp_caps_a_budget(gpu_context):
    renderer = wt.Renderer(wt.load_scene("cornell"), SIZE, SIZE)
    renderer.render(3, seconds=3600.0)
    assert renderer.samples_per_pixel == 3


@pytest.mark.parametrize(("samples_per_dispatch", "submits"), [(1, [1, 2, 4, 8]), (8, [1, 8, 16, 32])])
def test_stop_is_asked_before_every_submit(gpu_context, samples_per_dispatch, submits):
    renderer = wt.Renderer(wt.load_scene("cornell"), SIZE, SIZE, samples_per_dispatch=samples_per_dispatch)
    batches = []
    renderer.render(progress=batches.append, stop=lambda: len(batches) == 4)
    assert batches == submits and renderer.samples_per_pixel == sum(submits)
