"""Temporal antialiasing of the upsampled, filtered picture (TemporalAntialiasing): every pixel shows
the motion its history was taken along (closed form for a pan past a card); while moving the
output is the last output along that motion, clamped to this frame's 3x3 neighbourhood and
blended (a numpy model of the kernel); at rest and after a restart it is the filtered picture bit
for bit; and it steadies the picture of a pan (frame-to-frame change)."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Renderer, default_scene
from wgputrace.gpu.buffers import read_buffer
from wgputrace.gpu.layout import GBUFFER_PIXEL
from wgputrace.render.svgf_filter import picture_image
from wgputrace.render.temporal_antialiasing import ANTIALIASING_BLEND
from wgputrace.testing.reprojection import SIZE, card_scene, centre_hits, pinhole, pixel_centres, raster_of

pytestmark = pytest.mark.gpu

FACTOR = 4
WIDTH, HEIGHT = 64, 48


def _pan(step: int) -> Camera:
    return Camera(position=(0.004 * step, 0.31, -1.2), forward=(0.0, 0.0, 1.0), vfov_degrees=53.13)


def _surfaces(renderer: Renderer) -> np.ndarray:
    """What each pixel of the upsampled picture shows (GBUFFER_PIXEL records), (height, width)."""
    records = read_buffer(
        renderer.context, renderer._upsampling.surfaces, GBUFFER_PIXEL.dtype, renderer.width * renderer.height
    )
    return records.reshape(renderer.height, renderer.width)


def _filtered(renderer: Renderer) -> np.ndarray:
    """The last frame's filtered picture, before antialiasing."""
    return picture_image(renderer.context, renderer._filter.filtered, renderer.width, renderer.height)


def test_every_pixel_shows_the_motion_its_history_took():
    scene = card_scene()
    renderer = Renderer(scene, SIZE, SIZE, max_depth=1)
    for _ in range(FACTOR * FACTOR):
        renderer.render_frame(pinhole(0.0), upscale=FACTOR, filtered=True)
    renderer.render_frame(pinhole(0.25), upscale=FACTOR, filtered=True)
    surfaces = _surfaces(renderer)
    points, on_card = centre_hits(pinhole(0.25))
    # pixel centres at integers, as the kernels take them
    expected = raster_of(pinhole(0.0), points) - pixel_centres()
    # away from the card's edges every traced pixel near a pixel sees its plane
    near = np.zeros_like(on_card)
    for dy in range(-FACTOR, FACTOR + 1):
        for dx in range(-FACTOR, FACTOR + 1):
            near |= np.roll(on_card, (dy, dx), axis=(0, 1)) != on_card
    inner = np.zeros_like(on_card)
    inner[FACTOR:-FACTOR, FACTOR:-FACTOR] = True
    checked = inner & ~near
    assert checked[on_card].any() and checked[~on_card].any()
    np.testing.assert_allclose(surfaces["motion"][checked], expected[checked], atol=1e-3)
    # the card is nearer than the wall: it moves across the image further
    assert abs(expected[on_card & checked][0, 0]) > abs(expected[~on_card & checked][0, 0]) + 0.5
    assert (surfaces["previous_depth"][checked] > 0.0).all()


def _model(previous: np.ndarray, current: np.ndarray, surfaces: np.ndarray) -> np.ndarray:
    """The kernel's output in numpy: the last output bilinear along each pixel's motion (taps
    inside the image), clamped to the 3x3 neighbourhood's per-channel range, ANTIALIASING_BLEND of
    `current` blended in; `current` where the previous camera did not see the point."""
    height, width = current.shape[:2]
    rows, columns = np.mgrid[0:height, 0:width]
    position = np.stack([columns, rows], axis=-1) + surfaces["motion"].astype(np.float64)
    corner = np.floor(position).astype(int)
    fraction = position - corner
    colour, weights = np.zeros(current.shape), np.zeros(current.shape[:2])
    for dx in (0, 1):
        for dy in (0, 1):
            weight = (fraction[..., 0] if dx else 1 - fraction[..., 0]) * (
                fraction[..., 1] if dy else 1 - fraction[..., 1]
            )
            x, y = corner[..., 0] + dx, corner[..., 1] + dy
            inside = (0 <= x) & (x < width) & (0 <= y) & (y < height)
            tap = previous[np.clip(y, 0, height - 1), np.clip(x, 0, width - 1)]
            colour += np.where(inside[..., None], weight[..., None] * tap, 0.0)
            weights += np.where(inside, weight, 0.0)
    padded = np.pad(current, ((1, 1), (1, 1), (0, 0)), mode="edge")
    around = np.stack([padded[dy : dy + height, dx : dx + width] for dy in range(3) for dx in range(3)])
    kept = np.clip(colour / np.maximum(weights, 1e-30)[..., None], around.min(0), around.max(0))
    blended = ANTIALIASING_BLEND * current + (1.0 - ANTIALIASING_BLEND) * kept
    taken = (surfaces["previous_depth"] > 0.0) & (weights > 0.0)
    return np.where(taken[..., None], blended, current)


# and an odd size, whose last workgroups overhang the image
@pytest.mark.parametrize(("width", "height"), [(WIDTH, HEIGHT), (33, 31)])
def test_a_moving_pixel_is_the_last_output_along_its_motion_clamped_and_blended(width, height):
    renderer = Renderer(default_scene(), width, height, seed=3)
    output = None
    for step in range(6):
        previous = output
        output = renderer.render_frame(_pan(step), upscale=FACTOR, filtered=True)
    current = _filtered(renderer)
    expected = _model(previous, current, _surfaces(renderer))
    np.testing.assert_allclose(output, expected, rtol=1e-4, atol=1e-6)
    # most pixels took their last output: the blend is not the filtered picture
    assert (np.abs(output - current).max(axis=-1) > 1e-4).mean() > 0.5


def test_at_rest_and_after_a_restart_the_output_is_the_filtered_picture():
    renderer = Renderer(default_scene(), WIDTH, HEIGHT, seed=3)
    for step in range(3):
        renderer.render_frame(_pan(step), upscale=FACTOR, filtered=True)
    renderer.restart()
    first = renderer.render_frame(_pan(3), upscale=FACTOR, filtered=True)
    np.testing.assert_array_equal(first, _filtered(renderer))
    for _ in range(3):
        resting = renderer.render_frame(upscale=FACTOR, filtered=True)
        np.testing.assert_array_equal(resting, _filtered(renderer))


# Measured with seeds 1 to 4: the output's frame-to-frame change is 0.437 to 0.445 of the filtered
# picture's on this pan (1 without the blend).
STEADIER_RATIO = 0.55


@pytest.mark.parametrize("seed", [1])
def test_a_pan_is_steadier_than_its_filtered_pictures(seed):
    renderer = Renderer(default_scene(), WIDTH, HEIGHT, seed=seed)
    shown, filtered = [], []
    for step in range(16):
        shown.append(renderer.render_frame(_pan(step), upscale=FACTOR, filtered=True))
        filtered.append(_filtered(renderer))

    def change(pictures: list[np.ndarray]) -> float:
        # after the first frames, whose history is young
        steps = np.diff(np.array(pictures[4:]) ** (1 / 2.2), axis=0)
        return float(np.sqrt(np.mean(steps**2)))

    assert change(shown) < STEADIER_RATIO * change(filtered), (change(shown), change(filtered))
