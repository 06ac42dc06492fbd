"""Tone mapping (wgputrace.image_io): each curve at sample points of its published code, the
properties its authors state, exposure in stops and auto-exposure, and the PNG writer using them.
The viewer's shader is held to these curves in tests/view/test_tone_curves.py."""

from __future__ import annotations

import colorsys
import math

import numpy as np
import pytest
from PIL import Image

import wgputrace as wt
from wgputrace.image_io import (
    MIDDLE_GREY,
    TONEMAP_OPERATORS,
    auto_exposure,
    linear_to_srgb,
    srgb8,
    tone_curve,
    tonemap,
)

# The published code (Khronos's pbrNeutral.glsl, three.js r162's AgXToneMapping, Hill's
# ACESFitted in BakingLab's ACES.hlsl) transcribed line by line in scalar float64 Python, with
# GLSL's column-major matrices, and evaluated at these points once; the values are kept here.
PUBLISHED = {
    "pbr_neutral": {
        (0.18, 0.18, 0.18): (0.14, 0.14, 0.14),
        (1.0, 1.0, 1.0): (0.8690909, 0.8690909, 0.8690909),
        (0.5, 0.2, 0.05): (0.465625, 0.165625, 0.015625),
        (4.0, 1.5, 0.3): (0.9832558, 0.5541253, 0.3481426),
        (20.0, 30.0, 50.0): (0.9269548, 0.9509148, 0.998835),
    },
    "agx": {
        (0.18, 0.18, 0.18): (0.2145243, 0.2145204, 0.2145145),
        (1.0, 1.0, 1.0): (0.5901958, 0.590161, 0.5901236),
        (0.5, 0.2, 0.05): (0.4447984, 0.2330776, 0.1010596),
        (4.0, 1.5, 0.3): (0.9095133, 0.6907636, 0.4757286),
        (20.0, 30.0, 50.0): (0.9969783, 0.9968787, 0.996779),
    },
    "aces": {
        (0.18, 0.18, 0.18): (0.1055912, 0.1055912, 0.1055902),
        (1.0, 1.0, 1.0): (0.6191154, 0.6191154, 0.6191092),
        (0.5, 0.2, 0.05): (0.3644978, 0.1284064, 0.0225841),
        (4.0, 1.5, 0.3): (0.95974, 0.7553026, 0.3917884),
        (20.0, 30.0, 50.0): (0.9975727, 1.0, 1.0),
    },
}
# the tabulated values' rounding
PUBLISHED_ATOL = 1e-7


@pytest.mark.parametrize("operator", sorted(PUBLISHED))
def test_each_curve_is_its_published_code_at_sample_points(operator):
    points = np.array(list(PUBLISHED[operator]))
    expected = np.array(list(PUBLISHED[operator].values()))
    np.testing.assert_allclose(tone_curve(points, operator), expected, atol=PUBLISHED_ATOL)


def test_pbr_neutral_keeps_its_specifications_promises(rng):
    """The Khronos specification: base colours in [0.08, 0.8] come out less F90 = 0.04 exactly, no
    colour changes its hue (the output stays in the plane of the input and white), and the curve
    approaches white without reaching it."""
    base = rng.uniform(0.08, 0.8, (200, 3))
    np.testing.assert_allclose(tone_curve(base, "pbr_neutral"), base - 0.04, atol=1e-15)
    bright = rng.uniform(0.0, 50.0, (200, 3))
    out = tone_curve(bright, "pbr_neutral")
    plane_normal = np.cross(bright, np.ones(3))
    assert np.abs(np.sum(plane_normal * out, axis=1)).max() < 1e-12 * np.abs(plane_normal).max()
    assert (out < 1.0).all() and tone_curve(np.array([[1e6] * 3]), "pbr_neutral").min() > 0.9999


def test_agx_shows_middle_grey_as_half_grey_and_aces_as_a_tenth():
    """AgX's log encoding centres its sigmoid on middle grey: 0.18 shows at half the display's code
    values. The ACES output transform for sRGB puts middle grey at 10% of the display's white,
    which Hill's fit reproduces within 6%."""
    grey = np.full((1, 3), MIDDLE_GREY)
    assert linear_to_srgb(tone_curve(grey, "agx")) == pytest.approx(0.5, abs=2e-3)
    assert tone_curve(grey, "aces") == pytest.approx(0.10, rel=0.06)


@pytest.mark.parametrize("operator", TONEMAP_OPERATORS)
def test_every_curve_rises_from_black_and_stays_in_the_display(operator):
    levels = np.geomspace(1e-4, 1e4, 400)
    grey = tone_curve(np.repeat(levels[:, None], 3, axis=1), operator)[:, 1]
    assert (np.diff(grey) >= 0).all() and grey[0] < 0.01 and grey[-1] > 0.99
    assert tone_curve(np.zeros((1, 3)), operator).max() == pytest.approx(0.0, abs=1e-6)
    colours = tone_curve(np.random.default_rng(3).exponential(5.0, (500, 3)), operator)
    assert (colours >= 0).all() and (colours <= 1).all()


def hue_degrees(rgb: np.ndarray) -> np.ndarray:
    return np.array([colorsys.rgb_to_hsv(*c)[0] * 360.0 for c in rgb])


def test_bright_orange_keeps_its_hue_where_clipping_turns_it_yellow():
    """An orange surface lit 2 to 16 times past white: clipping turns it yellow then white; PBR
    Neutral keeps its hue exactly, AgX and ACES within 25 degrees."""
    orange = np.array([0.9, 0.35, 0.08])
    lit = orange * np.geomspace(2.0, 16.0, 7)[:, None]
    linear_hue = hue_degrees(orange[None])[0]
    shift = {op: np.abs(hue_degrees(tone_curve(lit, op)) - linear_hue).max() for op in TONEMAP_OPERATORS}
    assert shift["clip"] > 35.0
    assert shift["pbr_neutral"] < 1e-6
    assert shift["agx"] < 25.0 and shift["aces"] < 25.0


def test_exposure_is_in_stops_and_auto_finds_middle_grey(rng):
    image = rng.exponential(0.3, (16, 24, 3)).astype(np.float32)
    np.testing.assert_array_equal(tonemap(image, "agx", 1.0), tonemap(image * 2, "agx", 0.0))
    stops = auto_exposure(image)
    luminance = image.astype(np.float64) @ [0.2126, 0.7152, 0.0722] * 2.0**stops
    assert math.exp(np.mean(np.log(luminance))) == pytest.approx(MIDDLE_GREY, rel=1e-9)
    np.testing.assert_array_equal(tonemap(image, "aces", "auto"), tonemap(image, "aces", stops))
    assert auto_exposure(np.zeros((2, 2, 3))) == pytest.approx(math.log2(MIDDLE_GREY / 1e-4))
    assert auto_exposure(np.full((2, 2, 3), np.nan)) == 0.0


@pytest.mark.parametrize("operator", TONEMAP_OPERATORS)
def test_infinite_radiance_is_white_and_nan_black_through_every_curve(operator):
    """White as an 8-bit PNG shows it (AgX's sigmoid ends at 0.9987 encoded), with no overflow."""
    values = np.array([[[np.inf, 1e300, 1e20], [np.nan, 0.0, 0.0]]])
    np.testing.assert_array_equal(srgb8(tonemap(values, operator))[0, 0], 255)
    np.testing.assert_array_equal(tonemap(values, operator)[0, 1], tonemap(np.zeros((1, 1, 3)), operator)[0, 0])


def test_clip_at_zero_stops_is_the_png_of_before():
    """The default PNG is unchanged: radiance clipped at 1, sRGB-encoded, rounded (Mitsuba's)."""
    values = np.array([[[0.0, 0.25, 0.5], [0.75, 1.0, 7.0], [np.nan, np.inf, -2.0]]], np.float32)
    clipped = np.nan_to_num(values.astype(np.float64), nan=0.0, posinf=1.0, neginf=0.0)
    expected = np.round(linear_to_srgb(clipped) * 255.0).astype(np.uint8)
    np.testing.assert_array_equal(srgb8(tonemap(values)), expected)


def test_a_png_is_written_through_the_curve_asked_for(tmp_path, rng):
    image = rng.exponential(1.5, (6, 5, 3)).astype(np.float32)
    for operator in TONEMAP_OPERATORS:
        path = wt.save_image(tmp_path / f"{operator}.png", image, exposure=-0.5, tonemap=operator)
        expected = srgb8(tonemap(image, operator, -0.5))
        np.testing.assert_array_equal(np.asarray(Image.open(path).convert("RGB")), expected)
    # linear files keep their values whatever the curve
    exr = wt.save_image(tmp_path / "linear.exr", image, exposure=3.0, tonemap="agx")
    np.testing.assert_array_equal(wt.load_image(exr), image)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda image: tonemap(image, "filmic"), "tonemap must be one of clip, pbr_neutral, agx, aces, got 'filmic'"),
        (lambda image: tonemap(image, "agx", math.nan), "exposure must be a finite number of stops"),
        (lambda image: tonemap(image, "agx", "bright"), "or 'auto', got 'bright'"),
        (lambda image: wt.save_image("x.png", image, tonemap="Reinhard"), "got 'Reinhard'"),
    ],
)
def test_bad_tone_settings_are_one_line_errors(call, message):
    with pytest.raises(ValueError, match=message):
        call(np.zeros((2, 2, 3), np.float32))
