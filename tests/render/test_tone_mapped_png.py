"""A PNG of an HDR scene keeps its highlights' hue: the sunlit orange sphere of `sunlit_spheres`,
whose lit side is about four times brighter than white, turns yellow where the PNG clips each
channel at 1, and stays orange through AgX (and exactly its hue through Khronos PBR Neutral)."""

from __future__ import annotations

import colorsys

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.scenes.sunlit import ORANGE

pytestmark = pytest.mark.gpu

SIZE = (96, 64)
SPP = 16
# The orange sphere's lit side: pixels of the orange's hue (within this many degrees) whose red
# radiance is past white by this factor.
HUE_WINDOW_DEGREES = 10.0
PAST_WHITE = 1.5
# Yellow is 60 degrees, orange 20: clipping takes the lit side more than halfway there.
CLIPPED_SHIFT_DEGREES = 25.0
AGX_SHIFT_DEGREES = 12.0
# 8-bit rounding moves a hue by a fraction of a degree
NEUTRAL_SHIFT_DEGREES = 1.0


def hues(rgb: np.ndarray) -> np.ndarray:
    return np.array([colorsys.rgb_to_hsv(*c)[0] * 360.0 for c in rgb.reshape(-1, 3).astype(np.float64)])


def hue_shift(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs((a - b + 180.0) % 360.0 - 180.0)


def test_a_sunlit_orange_keeps_its_hue_in_the_png(gpu_context, tmp_path):
    image = wt.render(wt.load_scene("sunlit_spheres"), SPP, *SIZE, seed=3)
    linear_hues = hues(image)
    orange_hue = hues(np.array(ORANGE))[0]
    lit = (hue_shift(linear_hues, orange_hue) < HUE_WINDOW_DEGREES) & (image.reshape(-1, 3)[:, 0] > PAST_WHITE)
    assert lit.sum() > 100, "the orange sphere's lit side is not in the picture"
    shift = {}
    for operator in ("clip", "pbr_neutral", "agx"):
        png = wt.load_image(wt.save_image(tmp_path / f"{operator}.png", image, tonemap=operator))
        shift[operator] = float(np.median(hue_shift(hues(png)[lit], linear_hues[lit])))
        if operator == "agx":
            saturation = np.median([colorsys.rgb_to_hsv(*c)[1] for c in png.reshape(-1, 3)[lit]])
            assert saturation > 0.4, f"AgX washed the orange out to saturation {saturation:.2f}"
    assert shift["clip"] > CLIPPED_SHIFT_DEGREES, shift
    assert shift["agx"] < AGX_SHIFT_DEGREES, shift
    assert shift["pbr_neutral"] < NEUTRAL_SHIFT_DEGREES, shift
