"""Temporal upsampling (`render_frame(upscale=f)`, TemporalUpsampling): the Bayer order visits every
pixel of a block once per f * f frames; a resting camera's picture is render()'s mean bit for bit;
a pan carries the card's history to the pixels the closed form puts it (wgputrace.testing.reprojection);
the first frame is finite and black only near black samples; moving frames beat the blocky
nearest-neighbour upscale of the same samples against a converged reference, and the
variance-guided filter improves them further."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Renderer, default_scene
from wgputrace.integrators import integrator
from wgputrace.kernels.variant import KernelVariant
from wgputrace.render.temporal_upsampling import (
    INTERPOLATED_SAMPLE_WEIGHT,
    UPSCALE_FACTORS,
    history_cap,
    subset_offset,
)
from wgputrace.testing.image_statistics import displayed_psnr
from wgputrace.testing.reprojection import (
    SIZE,
    card_move,
    card_object,
    card_scene,
    centre_hits,
    pinhole,
    reprojection_taps,
)

# The lamp card's radiance: seen directly (max_depth 1) every sample of a card pixel is this, of a
# black wall pixel 0.
LAMP = 2.0


@pytest.mark.parametrize("factor", UPSCALE_FACTORS)
def test_the_bayer_order_visits_every_pixel_of_a_block_once_per_cycle(factor):
    cycle = factor * factor
    offsets = [subset_offset(frame, factor) for frame in range(2 * cycle)]
    assert sorted(offsets[:cycle]) == [(x, y) for x in range(factor) for y in range(factor)]
    assert offsets[cycle:] == offsets[:cycle]
    # low discrepancy: every aligned run of 4**k frames visits each cell of the block's
    # 2**k x 2**k partition once
    level = 1
    while level <= factor:
        side = factor // level
        for start in range(0, cycle, level * level):
            cells = {(x // side, y // side) for x, y in offsets[start : start + level * level]}
            assert len(cells) == level * level, (level, start)
        level *= 2


@pytest.mark.gpu
@pytest.mark.parametrize(("factor", "sampler"), [(2, "sobol"), (4, "independent")])
def test_a_resting_camera_is_the_plain_mean_bit_for_bit(factor, sampler):
    # every pixel takes its own sequence's samples, one per cycle of factor**2 frames: after two
    # cycles, the first two samples render() gives it
    frames = Renderer(default_scene(), 24, 20, seed=7, sampler=sampler)
    for _ in range(2 * factor * factor):
        image = frames.render_frame(spp=1, upscale=factor)
    plain = Renderer(default_scene(), 24, 20, seed=7, sampler=sampler)
    plain.render(2)
    np.testing.assert_array_equal(image, plain.image())


def _frame_samples(renderer: Renderer, frame: int, factor: int) -> np.ndarray:
    """The traced pixels' samples of frame number `frame` (one sample each): (rows, columns, 3)."""
    offset_x, offset_y = subset_offset(frame, factor)
    records = renderer._accumulated()
    sums = (records["sum"][:, :3] - records["compensation"][:, :3]).reshape(renderer.height, renderer.width, 3)
    return sums[offset_y::factor, offset_x::factor]


@pytest.mark.gpu
@pytest.mark.parametrize("factor", [2, 4])
def test_the_first_frame_is_finite_and_black_only_near_black_samples(factor):
    renderer = Renderer(card_scene(), SIZE, SIZE)
    image = renderer.render_frame(spp=1, upscale=factor)
    assert np.isfinite(image).all()
    # a pixel shows its nearest sample with a positive weight, and radiance is never negative: it
    # is black only where that sample is, and each sample is nearest to at most (2 factor)**2
    # pixels (factor**2 but at the image's border)
    black_samples = (_frame_samples(renderer, 0, factor).max(axis=-1) == 0.0).sum()
    assert (image.max(axis=-1) == 0.0).sum() <= (2 * factor) ** 2 * black_samples


def _lamp_card_renderer() -> Renderer:
    # max_depth 1: each pixel is what it sees directly, the same every sample
    scene = card_scene(wall=Diffuse("black", color=(0.0, 0.0, 0.0)), card=Emitter("lamp", emittance=LAMP))
    return Renderer(scene, SIZE, SIZE, max_depth=1)


def _grown(mask: np.ndarray, margin: int) -> np.ndarray:
    """`mask` grown by `margin` pixels in every direction (a square), not past the image."""
    padded = np.pad(mask, margin)
    grown = np.zeros_like(mask)
    for dy in range(2 * margin + 1):
        for dx in range(2 * margin + 1):
            grown |= padded[dy : dy + mask.shape[0], dx : dx + mask.shape[1]]
    return grown


def _on_card_near(on_card: np.ndarray, margin: int) -> np.ndarray:
    """Pixels within `margin` pixels (in x or y) of a pixel on the other plane."""
    return _grown(on_card, margin) & _grown(~on_card, margin)


@pytest.mark.gpu
@pytest.mark.parametrize("factor", [2, 4])
def test_a_pan_carries_the_card_to_the_pixels_the_closed_form_puts_it(factor):
    renderer = _lamp_card_renderer()
    for _ in range(factor * factor):
        renderer.render_frame(pinhole(0.0), upscale=factor)
    # the card moves 5 pixels, the wall 2.5: the card's history moves whole pixels
    image = renderer.render_frame(pinhole(0.625), upscale=factor)
    _, on_card = centre_hits(pinhole(0.625))
    # a pixel takes the motion of a traced pixel near it, which within `factor` pixels of the
    # card's edge may see the other plane
    away = ~_on_card_near(on_card, factor)
    np.testing.assert_array_equal(image[..., 0][away], np.where(on_card, LAMP, 0.0)[away])
    # the pixels not traced this frame kept a history exactly where the closed form's taps saw
    # their plane (a history left where it was would be rejected over the card's 5 new columns);
    # within `factor` pixels of the image's border the traced pixels around give no slope across
    # the wall, whose depth test is then strict
    traced = np.zeros_like(on_card)
    offset_x, offset_y = subset_offset(factor * factor, factor)
    traced[offset_y::factor, offset_x::factor] = True
    lengths = renderer._upsampling.records()["length"].reshape(SIZE, SIZE)
    inner = np.zeros_like(on_card)
    inner[factor:-factor, factor:-factor] = True
    checked = away & ~traced & inner
    kept = reprojection_taps(pinhole(0.0), pinhole(0.625))
    # among them pixels that saw the other plane before the pan
    assert (checked & (on_card != centre_hits(pinhole(0.0))[1])).any()
    np.testing.assert_array_equal(lengths[checked] > 0.0, kept[checked])


@pytest.mark.gpu
def test_a_moving_history_is_capped_and_grows_again_at_rest():
    factor, cycles = 2, 12
    cap = history_cap(factor, 1)
    assert cap < cycles
    renderer = Renderer(card_scene(), SIZE, SIZE)
    for _ in range(cycles * factor * factor):
        renderer.render_frame(pinhole(0.0), upscale=factor)

    def lengths() -> np.ndarray:
        return renderer._upsampling.records()["length"].reshape(SIZE, SIZE)

    assert (lengths() == cycles).all()
    renderer.render_frame(pinhole(0.01), upscale=factor)
    kept = reprojection_taps(pinhole(0.0), pinhole(0.01))
    traced = np.zeros_like(kept)
    offset_x, offset_y = subset_offset(cycles * factor * factor, factor)
    traced[offset_y::factor, offset_x::factor] = True
    moved = lengths()
    # a pixel not traced adds the samples interpolated around it on its surface, where there are any
    untraced = moved[kept & ~traced]
    assert np.isin(untraced, [cap, cap + INTERPOLATED_SAMPLE_WEIGHT]).all()
    assert (untraced == cap + INTERPOLATED_SAMPLE_WEIGHT).mean() > 0.9
    np.testing.assert_array_equal(moved[kept & traced], cap + 1)
    # at rest a cycle adds one sample to every pixel, as render() would
    for _ in range(factor * factor):
        renderer.render_frame(upscale=factor)
    np.testing.assert_array_equal(lengths(), moved + 1)


@pytest.mark.gpu
@pytest.mark.parametrize("factor", [2, 4])
def test_a_sliding_lamp_leaves_no_colour_on_the_wall_behind_it(factor):
    # max_depth 1: the white wall shows the grey sky alone, its red and green equal in every
    # sample, so any red on it came from the red lamp's history or samples
    scene = card_scene(card=Emitter("red lamp", color=(1.0, 0.1, 0.1), emittance=2.0))
    renderer = Renderer(scene, SIZE, SIZE, max_depth=1)
    for _ in range(factor * factor):
        renderer.render_frame(pinhole(0.0), upscale=factor)
    _, covered = centre_hits(pinhole(0.0))
    for step in range(1, 5):
        move = card_move((2.0 * step, 0.0))
        card_object(scene).transform = move
        image = renderer.render_frame(upscale=factor)
        _, on_card = centre_hits(pinhole(0.0), card=move)
        # the card's pixels and those whose motion or interpolation may be the card's (a traced
        # pixel on it near them)
        away = ~_grown(on_card, factor)
        covered |= on_card
        red = image[..., 0] - image[..., 1]
        assert not red[away].any(), f"frame {step}: the card's colour left on {np.count_nonzero(red[away])} pixels"
    # among the pixels checked, wall the card had covered
    assert (covered & away & ~on_card).any()


def _pan(step: int) -> Camera:
    return Camera(position=(0.004 * step, 0.31, -1.2), forward=(0.0, 0.0, 1.0), vfov_degrees=53.13)


# Measured with seeds 5 to 8 (sRGB PSNR against 256 samples per pixel): 2x gains 6.35 to 6.76 dB
# over the blocky upscale, 4x 4.77 to 5.56 dB; without the interpolated samples a moving history
# takes (INTERPOLATED_SAMPLE_WEIGHT), 4.63 to 4.77 and 2.50 to 2.82 dB.
@pytest.mark.gpu
@pytest.mark.parametrize(("factor", "gain_db"), [(2, 5.5), (4, 3.8)])
def test_moving_frames_beat_the_blocky_upscale_of_the_same_samples(factor, gain_db):
    width, height, frames = 64, 48, 12
    renderer = Renderer(default_scene(), width, height, seed=5)
    for step in range(frames):
        image = renderer.render_frame(_pan(step), upscale=factor)
    # this frame's samples, one per block, each copied over its block
    low = _frame_samples(renderer, frames - 1, factor)
    blocky = np.repeat(np.repeat(low, factor, axis=0), factor, axis=1)
    reference = Renderer(default_scene(), width, height, seed=11)
    reference.set_camera(_pan(frames - 1))
    reference.render(256)
    upsampled_db = displayed_psnr(image, reference.image())
    blocky_db = displayed_psnr(blocky, reference.image())
    assert upsampled_db > blocky_db + gain_db, (upsampled_db, blocky_db)


# Measured with seeds 5 to 8: the filter adds 0.79 to 1.66 dB at 2x (0.35 to 0.59 at 4x, where the
# interpolated samples smooth the unfiltered picture more).
@pytest.mark.gpu
def test_the_variance_guided_filter_improves_upsampled_frames():
    width, height, frames, factor = 64, 48, 12, 2
    pictures = {}
    for filtered in (False, True):
        renderer = Renderer(default_scene(), width, height, seed=5)
        for step in range(frames):
            pictures[filtered] = renderer.render_frame(_pan(step), upscale=factor, filtered=filtered)
    assert np.isfinite(pictures[True]).all()
    reference = Renderer(default_scene(), width, height, seed=11)
    reference.set_camera(_pan(frames - 1))
    reference.render(256)
    gain = displayed_psnr(pictures[True], reference.image()) - displayed_psnr(pictures[False], reference.image())
    assert gain > 0.4, gain


@pytest.mark.gpu
def test_upscale_is_refused_where_it_cannot_work():
    renderer = Renderer(default_scene(), 16, 12)
    with pytest.raises(ValueError, match="upscale must be 1 or one of"):
        renderer.render_frame(upscale=3)
    with pytest.raises(ValueError, match="at least 8x8 pixels, got 16x4"):
        Renderer(default_scene(), 16, 4).render_frame(upscale=8)


def test_only_integrators_with_a_subset_kernel_compile_one():
    with pytest.raises(ValueError, match="the bdpt integrator has no kernel over a subset of pixels"):
        KernelVariant(integrator=integrator("bdpt"), subset=True)
    with pytest.raises(ValueError, match="a band of rows, a subset of pixels or a pre-pass, not two of them"):
        KernelVariant(integrator=integrator("mis"), rows=True, subset=True)
    subset = KernelVariant(integrator=integrator("mis"), subset=True, samples_per_dispatch=8, loop_budget=True)
    assert subset.entry == ("integrators/path_tracer_subset.wgsl", "main_subset")
    assert (subset.samples_per_dispatch, subset.loop_budget) == (1, False)
    assert "subset" in {group.name for group in subset.groups()}
