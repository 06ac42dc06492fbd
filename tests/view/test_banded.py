"""Bands of rows within a time budget add exactly the samples whole-image dispatches add."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Renderer, default_scene
from wgputrace.gpu.buffers import read_buffer
from wgputrace.gpu.layout import ACCUMULATED_PIXEL
from wgputrace.view.banded import BAND_ROWS_STEP, BandedRenderer
from wgputrace.view.display import Display, ViewSettings

pytestmark = pytest.mark.gpu

WIDTH, HEIGHT = 40, 30
SEED = 5
SPP = 3


@pytest.fixture(scope="module")
def scene():
    return default_scene()


# The viewer's mean is sum / count in float32, leaving out the Kahan compensation (below half an
# ulp of the sum), where Renderer.image() rounds (sum - compensation) / count once from float64.
RESOLVE_RTOL = 2.0**-22


def mean_image(banded: BandedRenderer) -> np.ndarray:
    display = Display(banded)
    display.render(ViewSettings())
    return display.read_image()


def accumulated(renderer: Renderer, pixels: int) -> np.ndarray:
    return read_buffer(renderer.context, renderer.resources["accumulation"], ACCUMULATED_PIXEL.dtype, pixels)


def test_bands_give_the_image_of_whole_dispatches_bit_for_bit(gpu_context, scene):
    banded = BandedRenderer(Renderer(scene, WIDTH, HEIGHT, seed=SEED))
    banded.restart(scene.camera)
    banded.seconds_per_sample = 1.0  # a budget of one band per call, however fast the adapter
    bands = 0
    while banded.samples_per_pixel < SPP:
        banded.advance(0.0)
        bands += 1
        assert banded.rows_done % BAND_ROWS_STEP == 0
    assert banded.rows_done == 0 and bands == SPP * -(-HEIGHT // BAND_ROWS_STEP)
    whole = Renderer(scene, WIDTH, HEIGHT, seed=SEED)
    whole.render(SPP)
    np.testing.assert_array_equal(accumulated(banded.renderer, WIDTH * HEIGHT), accumulated(whole, WIDTH * HEIGHT))
    np.testing.assert_allclose(mean_image(banded), whole.image(), rtol=RESOLVE_RTOL, atol=0)


def test_a_reduced_size_is_the_image_of_a_renderer_of_that_size(gpu_context, scene):
    """The pixel index (and so the random stream) of a pixel depends on the traced width only."""
    banded = BandedRenderer(Renderer(scene, WIDTH, HEIGHT, seed=SEED))
    reduced = (WIDTH // 4, HEIGHT // 4)
    banded.restart(scene.camera, reduced)
    banded.seconds_per_sample = 1.0
    banded.advance(SPP * reduced[0] * reduced[1], whole_pass=True)  # a budget of SPP whole passes in one call
    assert (banded.rows_done, banded.samples_per_pixel) == (0, SPP)
    expected = Renderer(scene, *reduced, seed=SEED)
    expected.render(banded.samples_per_pixel)
    pixels = reduced[0] * reduced[1]
    np.testing.assert_array_equal(accumulated(banded.renderer, pixels), accumulated(expected, pixels))
    np.testing.assert_allclose(mean_image(banded), expected.image(), rtol=RESOLVE_RTOL, atol=0)


def test_partial_passes_count_their_rows(gpu_context, scene):
    banded = BandedRenderer(Renderer(scene, WIDTH, HEIGHT, seed=SEED))
    banded.restart(scene.camera)
    banded.seconds_per_sample = 1.0
    banded.advance(0.0)
    assert (banded.samples_per_pixel, banded.rows_done) == (0, BAND_ROWS_STEP)
    assert banded.samples_done == pytest.approx(BAND_ROWS_STEP / HEIGHT)
    image = mean_image(banded)
    assert np.all(image[:BAND_ROWS_STEP].sum(axis=2).mean(axis=1) > 0)  # sampled rows have light
    assert np.all(image[BAND_ROWS_STEP:] == 0)  # the others have no sample and no fallback yet


def test_a_size_beyond_the_buffers_is_refused(gpu_context, scene):
    banded = BandedRenderer(Renderer(scene, WIDTH, HEIGHT, seed=SEED))
    with pytest.raises(ValueError, match=f"within the renderer's {WIDTH}x{HEIGHT}"):
        banded.restart(scene.camera, (WIDTH + 1, HEIGHT))


def test_resolving_only_the_new_rows_gives_the_full_resolve(gpu_context, scene):
    """At rest the viewer resolves just the band it traced; the picture must be the whole mean."""
    banded = BandedRenderer(Renderer(scene, WIDTH, HEIGHT, seed=SEED))
    banded.restart(scene.camera)
    display = Display(banded)
    banded.seconds_per_sample = 1.0
    for _ in range(2 * -(-HEIGHT // BAND_ROWS_STEP) + 1):  # two passes and a band: every row twice or three times
        banded.advance(0.0)
        display.render(ViewSettings())
    partial = display.read_image()
    display.camera_changed()  # forces a resolve of every row
    display.render(ViewSettings())
    np.testing.assert_array_equal(partial, display.read_image())
