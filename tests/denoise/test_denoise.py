"""wt.denoise through Intel Open Image Denoise (skipped without pyoidn): what it returns, that it
removes Monte Carlo-like noise, that guides keep detail colour alone loses, that it leaves a clean
image's level alone, and that threads and image sizes do not mix up its cached filters.

The noisy images are a clean one times gamma-distributed noise of mean 1, as the mean of SPP
exponential samples per pixel is: unbiased, and as heavy-tailed as a path tracer's at low spp."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

pyoidn = pytest.importorskip("pyoidn")

from wgputrace.denoise import CACHED_PIPELINES, QUALITIES, denoise, denoiser_available, denoiser_device  # noqa: E402

SIZE = 64
SPP = 1
# Measured 0.005 to 0.018 over seeds 0-7 and the three qualities (MSE after / MSE before).
NOISE_LEFT_BOUND = 0.1
# A 4-pixel checkerboard albedo at 1 spp: albedo and normal guides left 0.005 to 0.026 of the noisy
# image's MSE, colour alone 0.15 to 0.18 (seeds 0-7, all qualities); guided must do 3 times better.
GUIDED_GAIN = 3.0
CHECKER = 4
# The bias bound: a denoiser must not move a 32-pixel block's mean by more than 1%
# (0.13% measured on the clean gradient).
BLOCK = 32
BLOCK_BIAS_BOUND = 0.01


def gradient() -> np.ndarray:
    """A smooth, clean image in [0.2, 1]."""
    y, x = np.mgrid[0:SIZE, 0:SIZE] / (SIZE - 1)
    return np.stack([0.2 + 0.8 * x, 0.2 + 0.8 * y, np.full_like(x, 0.5)], axis=-1).astype(np.float32)


def noisy(clean: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    return (clean * rng.gamma(SPP, 1.0 / SPP, clean.shape)).astype(np.float32)


def mse(image: np.ndarray, clean: np.ndarray) -> float:
    return float(np.mean((image.astype(np.float64) - clean) ** 2))


def test_the_device_is_cuda_where_oidn_supports_it_else_the_cpu():
    assert denoiser_available()
    assert denoiser_device() == ("CUDA" if pyoidn.Device.is_cuda_available(0) else "CPU")


@pytest.mark.parametrize("quality", QUALITIES)
def test_denoising_removes_most_of_the_noise(rng, quality):
    clean = gradient()
    image = noisy(clean, rng)
    denoised = denoise(image, quality=quality)
    assert denoised.dtype == np.float32 and denoised.shape == image.shape
    assert np.all(np.isfinite(denoised))
    assert mse(denoised, clean) < NOISE_LEFT_BOUND * mse(image, clean)


def test_the_input_is_left_as_it_was(rng):
    image = noisy(gradient(), rng)
    before = image.copy()
    denoise(image, np.clip(image, 0, 1), np.zeros_like(image))
    np.testing.assert_array_equal(image, before)


@pytest.mark.parametrize("quality", QUALITIES)
def test_guides_keep_a_texture_that_colour_alone_blurs(rng, quality):
    y, x = np.mgrid[0:SIZE, 0:SIZE]
    squares = ((y // CHECKER + x // CHECKER) % 2).astype(np.float32)
    albedo = np.repeat((0.15 + 0.7 * squares)[..., None], 3, axis=2)
    normal = np.zeros_like(albedo)
    normal[..., 2] = 1.0
    clean = albedo  # lit by a uniform radiance of 1
    image = noisy(clean, rng)
    colour_only = mse(denoise(image, quality=quality), clean)
    guided = mse(denoise(image, albedo, normal, quality=quality), clean)
    assert guided * GUIDED_GAIN < colour_only


def test_a_clean_image_keeps_its_level():
    clean = gradient()
    denoised = denoise(clean)
    blocks = (SIZE // BLOCK, BLOCK, SIZE // BLOCK, BLOCK, 3)
    ratio = denoised.reshape(blocks).mean(axis=(1, 3)) / clean.reshape(blocks).mean(axis=(1, 3))
    assert np.max(np.abs(ratio - 1.0)) < BLOCK_BIAS_BOUND


def test_threads_and_sizes_get_their_own_results(rng):
    """More image configurations than are cached, denoised from several threads at once: each
    result equals the same image denoised alone."""
    shapes = [(SIZE - 8 * k, SIZE, 3) for k in range(CACHED_PIPELINES + 2)]
    images = [noisy(np.resize(gradient(), shape), rng) for shape in shapes]
    alone = [denoise(image) for image in images]
    with ThreadPoolExecutor(max_workers=3) as pool:
        together = list(pool.map(denoise, images * 2))
    for expected, got in zip(alone * 2, together, strict=True):
        np.testing.assert_array_equal(got, expected)
