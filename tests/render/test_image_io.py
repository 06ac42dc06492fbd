"""Image files: linear formats round-trip exactly, PNG is clipped sRGB."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import load_image, save_image
from wgputrace.image_io import linear_to_srgb, tonemap


def test_linear_formats_round_trip(tmp_path, rng):
    image = rng.exponential(2.0, (5, 7, 3)).astype(np.float32)
    for suffix in (".exr", ".npy"):
        np.testing.assert_array_equal(load_image(save_image(tmp_path / f"x{suffix}", image)), image)


def test_png_is_srgb_encoded_and_clipped(tmp_path):
    image = np.array([[[0.0, 0.5, 4.0], [0.0031308, 0.2, 1.0]]], dtype=np.float32)
    pixels = tonemap(image)
    assert pixels[0, 0].tolist() == [0, 188, 255]  # sRGB(0.5) = 0.7354
    decoded = load_image(save_image(tmp_path / "x.png", image))
    np.testing.assert_allclose(decoded, np.minimum(image, 1.0), atol=0.01)
    assert linear_to_srgb(np.array(1.0)) == pytest.approx(1.0)


def test_nan_never_reaches_a_png():
    pixels = tonemap(np.array([[[np.nan, np.inf, -1.0]]], dtype=np.float32))
    assert pixels.tolist() == [[[0, 255, 0]]]


def test_unknown_format_is_named(tmp_path):
    with pytest.raises(ValueError, match=r"unknown image format '\.tif'"):
        save_image(tmp_path / "x.tif", np.zeros((2, 2, 3), np.float32))
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        save_image(tmp_path / "x.npy", np.zeros((2, 2), np.float32))
