"""The moving picture upsampled (`TemporalPicture.frame(..., upscale=)`): its factor chosen from the
budget (FIRST_FACTOR first, 1 once a full frame is measured to fit), and every debug view of an
upscaled frame finite and not black: the raw frame is the traced pixels' samples, each over its
block, and the history length comes from the upsampled history."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from wgputrace import Renderer
from wgputrace.loaders import load_scene
from wgputrace.render.temporal_upsampling import subset_offset
from wgputrace.view.temporal_picture import FRAME_VIEWS, FrameView, TemporalPicture, traced_blocks
from wgputrace.view.upscale_choice import FIRST_FACTOR, choose_upscale

pytestmark = pytest.mark.gpu

SIZE = (64, 48)
STEP = 0.01  # the camera slides this far a frame
# A budget no frame fits, and one every frame fits (its frames trace one sample until measured).
NO_TIME = 1e-9
ALL_THE_TIME = 100.0
# Frames of the views' test: a few after each view's first, so each shows reprojected history.
FRAMES_PER_VIEW = 3


def _cameras(scene):
    camera = scene.camera
    for step in range(1000):
        yield dataclasses.replace(camera, position=tuple(np.add(camera.position, (STEP * step, 0.0, 0.0))))


@pytest.fixture
def picture(gpu_context):
    scene = load_scene("cornell")
    return TemporalPicture(Renderer(scene, *SIZE, seed=3)), _cameras(scene)


def test_the_factor_starts_in_the_middle_stays_upsampled_while_nothing_fits_and_is_1_once_a_full_frame_does(
    picture,
):
    moving, cameras = picture
    factors = []
    for _ in range(2):
        moving.frame(next(cameras), NO_TIME)
        factors.append(moving.upscale)
    # the first frame at a factor is not measured: the second is
    assert factors == [FIRST_FACTOR, FIRST_FACTOR] and list(moving.costs) == [FIRST_FACTOR]
    costs = dict(moving.costs)
    moving.frame(next(cameras), NO_TIME)
    factors.append(moving.upscale)
    # nothing fits, and no coarser factor so soon after the last switch
    assert factors[-1] == choose_upscale(costs, NO_TIME, SIZE, FIRST_FACTOR, 2) == FIRST_FACTOR
    assert moving.traced_size == (SIZE[0] // factors[-1], SIZE[1] // factors[-1])
    for _ in range(2):
        moving.frame(next(cameras), ALL_THE_TIME)
        factors.append(moving.upscale)
    assert factors[-2:] == [1, 1] and moving.traced_size == SIZE
    # a frame's samples before its factor's cost is measured: one
    assert moving.samples_per_pixel == 1


def test_a_given_factor_is_taken_as_given(picture):
    moving, cameras = picture
    moving.frame(next(cameras), ALL_THE_TIME, upscale=4)
    assert moving.upscale == 4 and moving.renderer.traced_subset() == (4, subset_offset(0, 4))
    moving.frame(next(cameras), ALL_THE_TIME, upscale=4)
    assert moving.renderer.traced_subset() == (4, subset_offset(1, 4))


@pytest.mark.parametrize("factor", [2, 8])
def test_every_debug_view_of_an_upscaled_frame_is_finite_and_not_black(picture, factor):
    moving, cameras = picture
    for view in FRAME_VIEWS:
        for _ in range(FRAMES_PER_VIEW):
            shown = moving.frame(next(cameras), NO_TIME, view, upscale=factor)
        assert moving.upscale == factor
        assert shown.shape == (SIZE[1], SIZE[0], 3) and np.isfinite(shown).all(), view
        assert shown.max() > 0.0 and shown.mean() > 0.05, f"{view.value} is black: mean {shown.mean()}"
        renderer = moving.renderer
        if view == FrameView.RAW:
            # the traced pixels' samples, each over its block: as many distinct colours as blocks
            subset = renderer.traced_subset()
            assert subset[0] == factor
            np.testing.assert_array_equal(shown, traced_blocks(renderer.image(), *subset))
            blocks = shown[::factor, ::factor]
            assert np.array_equal(np.repeat(np.repeat(blocks, factor, 0), factor, 1), shown)
        if view == FrameView.HISTORY:
            assert np.array_equal(shown[..., 0], shown[..., 2]), "the history length is shown in grey"
            length = renderer.history_length()
            assert length.max() > 0.0, "the upsampled history is empty"
            np.testing.assert_array_equal(shown[..., 0] > 0.0, length > 0.0)


def test_traced_blocks_fills_each_block_with_its_traced_pixel():
    image = np.arange(7 * 6, dtype=np.float32).reshape(7, 6, 1)
    blocks = traced_blocks(image, 4, (1, 2))[..., 0]
    assert (blocks[:4, :4] == image[2, 1, 0]).all() and (blocks[:4, 4:] == image[2, 5, 0]).all()
    # the blocks cut by the bottom edge hold their traced pixel (row 6)
    assert (blocks[4:, :4] == image[6, 1, 0]).all() and (blocks[4:, 4:] == image[6, 5, 0]).all()
    # one cut without it (only columns 4 and 5: the traced column 5 is there; at x = 3 it is not)
    cut = traced_blocks(image, 4, (3, 0))[..., 0]
    assert (cut[:4, 4:] == image[0, 3, 0]).all(), "a block without its traced pixel takes the previous block's"
