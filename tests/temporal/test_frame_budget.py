"""`Renderer.render_frame(budget=...)`: a frame traces until its time is spent, at least one sample
per pixel, `spp` capping it; the samples it took are counted in the history as a frame of that
many samples. No time is measured: a budget far below one pass, one far above the cap and one that
holds many passes of a tiny image pin the sample counts."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Renderer, default_scene

pytestmark = pytest.mark.gpu

SIZE = (24, 18)
SEED = 7
# far below any adapter's time for one pass: the frame still takes its one sample per pixel
TINY_BUDGET = 1e-9
# far above the time of CAPPED_SPP passes of SIZE on any adapter: the cap ends the frame
AMPLE_BUDGET = 600.0
CAPPED_SPP = 3
# a pass of SIZE takes milliseconds on lavapipe: this holds many of them on any adapter
SEVERAL_PASSES_BUDGET = 0.5


def _renderer() -> Renderer:
    return Renderer(default_scene(), *SIZE, seed=SEED)


def test_a_budget_below_one_pass_still_takes_one_sample_per_pixel():
    timed, counted = _renderer(), _renderer()
    for _ in range(2):
        image = timed.render_frame(budget=TINY_BUDGET)
        assert timed.stats.samples_per_pixel == 1
        expected = counted.render_frame(spp=1)
    np.testing.assert_array_equal(image, expected)
    assert (timed.history_length() == 2).all()


def test_spp_caps_a_budget():
    timed, counted = _renderer(), _renderer()
    image = timed.render_frame(spp=CAPPED_SPP, budget=AMPLE_BUDGET, filtered=True)
    assert timed.stats.samples_per_pixel == CAPPED_SPP
    np.testing.assert_array_equal(image, counted.render_frame(spp=CAPPED_SPP, filtered=True))
    assert (timed.history_length() == CAPPED_SPP).all()


def test_a_budget_traces_passes_until_it_is_spent():
    renderer = _renderer()
    renderer.render_frame(budget=SEVERAL_PASSES_BUDGET)
    samples = renderer.stats.samples_per_pixel
    assert samples > 1, "a budget of many passes traced one"
    assert (renderer.history_length() == samples).all()


@pytest.mark.parametrize("budget", [0.0, -1.0, float("nan")])
def test_a_budget_must_be_positive(budget):
    with pytest.raises(ValueError, match="budget must be > 0 seconds"):
        _renderer().render_frame(budget=budget)


def test_an_upsampled_frame_takes_its_budget_one_sample_at_a_time():
    timed, counted = _renderer(), _renderer()
    image = timed.render_frame(budget=TINY_BUDGET, upscale=2)
    assert timed.stats.samples_per_pixel == 1
    np.testing.assert_array_equal(image, counted.render_frame(spp=1, upscale=2))
    image = timed.render_frame(spp=CAPPED_SPP, budget=AMPLE_BUDGET, upscale=2)
    assert timed.stats.samples_per_pixel == CAPPED_SPP
    np.testing.assert_array_equal(image, counted.render_frame(spp=CAPPED_SPP, upscale=2))
