"""The viewer's tone mapping on the GPU: the shipped WGSL curves against wgputrace.image_io's numpy
ones, the auto-exposure pass's log average (and its smoothing over frames) against numpy, and the
present pass's picture against `tonemap`."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace.gpu.graphics import image_texture
from wgputrace.image_io import (
    LOG_AVERAGE_FLOOR,
    MIDDLE_GREY,
    REC709_LUMINANCE,
    TONEMAP_OPERATORS,
    linear_to_srgb,
    srgb8,
    tone_curve,
)
from wgputrace.render.display_constants import GENERATED_DISPLAY_CONSTANTS, display_constants
from wgputrace.testing.harness import run_per_case
from wgputrace.view.layout import IMAGE_FORMAT
from wgputrace.view.present import AUTO_EXPOSURE_SECONDS, Presenter, Tone

pytestmark = pytest.mark.gpu

# float32 matrices, log2, pow and divisions against float64
CURVE_ATOL = 2e-5
# the present pass's target encodes sRGB in float32 and rounds to 8 bits: at most one code off
SRGB_CODES = 1
SIZE = (37, 23)
# EXPOSURE_GRID of view/exposure.wgsl: the pixels the auto-exposure reads
EXPOSURE_GRID = 64


def colours(rng) -> np.ndarray:
    """Greys from 1e-4 to 1e3 and far beyond (where ACES's squares would overflow float32), and
    colours dim to very bright."""
    greys = np.repeat(np.geomspace(1e-4, 1e3, 40)[:, None], 3, axis=1)
    beyond = np.array([[1e20, 1e20, 1e20], [1e25, 2.0, 0.0]])
    return np.concatenate(
        [np.zeros((1, 3)), greys, beyond, rng.exponential(2.0, (200, 3)), rng.exponential(50.0, (60, 3))]
    )


@pytest.mark.parametrize("operator", TONEMAP_OPERATORS)
def test_the_shaders_curves_are_the_numpy_curves(gpu_context, rng, operator):
    values = colours(rng)
    shown = run_per_case(
        gpu_context,
        ["view/tone_curves.wgsl"],
        {"exposed": values},
        f"    return vec4<f32>(tone_curve(exposed, TONEMAP_{operator.upper()}), 0.0);",
        generated={GENERATED_DISPLAY_CONSTANTS: display_constants()},
    )[:, :3]
    np.testing.assert_allclose(shown, tone_curve(values.astype(np.float32), operator), atol=CURVE_ATOL)


def hdr_texture(gpu_context, values: np.ndarray):
    """An IMAGE_FORMAT texture of (H, W, 3) linear values, as the viewer's resolved picture."""
    height, width = values.shape[:2]
    texture = image_texture(gpu_context, "test picture", width, height, IMAGE_FORMAT)
    texels = np.ones((height, width, 4), np.float32)
    texels[..., :3] = values
    gpu_context.device.queue.write_texture(
        {"texture": texture}, texels, {"bytes_per_row": width * 16, "rows_per_image": height}, (width, height, 1)
    )
    return texture


def log_average(values: np.ndarray) -> float:
    """What the auto-exposure pass reads: the grid of pixels at (2 k + 1) size / (2 grid), those
    with a non-finite value left out."""
    height, width = values.shape[:2]
    grid = (min(width, EXPOSURE_GRID), min(height, EXPOSURE_GRID))
    columns = (2 * np.arange(grid[0]) + 1) * width // (2 * grid[0])
    rows = (2 * np.arange(grid[1]) + 1) * height // (2 * grid[1])
    read = values[np.ix_(rows, columns)].astype(np.float64).reshape(-1, 3)
    luminance = read[np.isfinite(read).all(axis=1)] @ REC709_LUMINANCE
    return float(np.mean(np.log(np.maximum(luminance, LOG_AVERAGE_FLOOR))))


def test_auto_exposure_measures_the_log_average_and_follows_it(gpu_context, rng):
    presenter = Presenter(gpu_context, "rgba8unorm")
    assert presenter.measured_log_average() is None
    first = rng.exponential(0.4, (*SIZE[::-1], 3)).astype(np.float32)
    first[3, 5] = np.nan  # left out of the average
    presenter.measure_exposure(hdr_texture(gpu_context, first), SIZE, 0.0, restart=True)
    expected = log_average(first)
    assert presenter.measured_log_average() == pytest.approx(expected, abs=1e-5)
    # one time constant later, a brighter picture has moved it 1 - 1/e of the way
    second = first * 8.0
    presenter.measure_exposure(hdr_texture(gpu_context, second), SIZE, AUTO_EXPOSURE_SECONDS)
    moved = expected + (1.0 - math.exp(-1.0)) * (log_average(second) - expected)
    assert presenter.measured_log_average() == pytest.approx(moved, abs=1e-4)


@pytest.mark.parametrize("operator", TONEMAP_OPERATORS)
def test_the_present_pass_shows_what_tonemap_computes(gpu_context, rng, operator):
    presenter = Presenter(gpu_context, "rgba8unorm")
    values = rng.exponential(1.0, (*SIZE[::-1], 3)).astype(np.float32)
    texture = hdr_texture(gpu_context, values)
    presenter.measure_exposure(texture, SIZE, 0.0, restart=True)
    tone = Tone(operator, ev=0.5, automatic=True)
    pixels = presenter.screenshot(texture, SIZE, SIZE, tone)
    scale = 2.0**0.5 * MIDDLE_GREY / math.exp(log_average(values))
    expected = srgb8(linear_to_srgb(tone_curve(values.astype(np.float64) * scale, operator)))
    assert np.abs(pixels.astype(int) - expected.astype(int)).max() <= SRGB_CODES
