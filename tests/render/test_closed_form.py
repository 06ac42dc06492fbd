"""Renders whose exact answer is known: furnaces made of a closed emitter."""

from __future__ import annotations

from statistics import NormalDist

import numpy as np
import pytest

from wgputrace import UNLIMITED_DEPTH, Diffuse, Renderer, Shape, render, save_image
from wgputrace.scene import DegenerateTrianglesWarning
from wgputrace.testing.scenes import (
    ENCLOSURE_RADIANCE,
    diffuse_sphere_in_emitter,
    glass_sphere_in_emitter,
    inside_emitter,
)

SIZE = 24
SEED = 7
# Float32 arithmetic along a path and in the Kahan sum: a few roundings of relative size 2^-24.
EXACT_RTOL = 1e-5
# Family-wise two-sided significance level of the z-tests below (3 tests x 3 channels), split by
# Sidak's correction; fixed seeds make them deterministic.
SIGNIFICANCE = 1e-3
Z_TESTS = 10
Z_LIMIT = NormalDist().inv_cdf(1 - (1 - (1 - SIGNIFICANCE) ** (1 / Z_TESTS)) / 2)


@pytest.mark.parametrize("max_depth", [1, 9, UNLIMITED_DEPTH])
@pytest.mark.parametrize("accel", ["bvh", "flat"])
def test_inside_closed_emitter_every_pixel_is_its_radiance(gpu_context, max_depth, accel):
    image = render(inside_emitter(), spp=2, width=SIZE, height=SIZE, seed=SEED, max_depth=max_depth, accel=accel)
    np.testing.assert_allclose(image, np.broadcast_to(ENCLOSURE_RADIANCE, image.shape), rtol=EXACT_RTOL)


def test_diffuse_sphere_in_emitter_reflects_albedo_times_radiance_exactly(gpu_context, failure_dir):
    """Every direction leaving a convex sphere hits the enclosure, and cosine sampling's weight is
    exactly the albedo: with BSDF sampling each sample on the sphere is albedo * L, zero variance.
    (The sphere fills the view: its angular radius, 30 degrees, exceeds half the field of view.)"""
    albedo = np.array([0.25, 0.5, 0.75])
    renderer = Renderer(diffuse_sphere_in_emitter(albedo), SIZE, SIZE, seed=SEED, max_depth=9, integrator="bsdf")
    renderer.render(4)
    image = renderer.image()
    expected = np.broadcast_to(albedo * ENCLOSURE_RADIANCE, image.shape)
    if not np.allclose(image, expected, rtol=EXACT_RTOL):
        save_image(failure_dir / "diffuse_sphere_in_emitter.exr", image)
    np.testing.assert_allclose(image, expected, rtol=EXACT_RTOL)
    # and with max_depth 1 the sphere is black: it emits nothing
    direct = render(diffuse_sphere_in_emitter(albedo), spp=1, width=SIZE, height=SIZE, seed=SEED, max_depth=1)
    assert np.all(direct == 0)


@pytest.mark.parametrize("integrator", ["nee", "mis", "bdpt"])
def test_light_sampling_in_emitter_converges_to_albedo_times_radiance(gpu_context, failure_dir, integrator):
    """With next-event estimation the same sphere is noisy (light samples hit the enclosure's
    triangles at varying distances and cosines) but unbiased: the image mean is z-tested against
    albedo * L with the standard error from the per-pixel spread. Emission found by BSDF sampling
    must be weighted out (NEE) or down (MIS), or the result doubles."""
    albedo = np.array([0.25, 0.5, 0.75])
    renderer = Renderer(diffuse_sphere_in_emitter(albedo), SIZE, SIZE, seed=SEED, max_depth=2, integrator=integrator)
    renderer.render(8)
    assert_mean_is(renderer, albedo * ENCLOSURE_RADIANCE, failure_dir / f"diffuse_sphere_{integrator}.exr")


def assert_mean_is(renderer: Renderer, expected: np.ndarray, failure_path) -> None:
    """z-test of the image mean (pixels are independent) against `expected`, per channel."""
    image = renderer.image().reshape(-1, 3).astype(np.float64)
    mean = image.mean(axis=0)
    standard_error = image.std(axis=0, ddof=1) / np.sqrt(len(image))
    # a noise-free image would make the test vacuous
    assert np.all(standard_error > 0)
    z = (mean - expected) / standard_error
    if np.any(np.abs(z) > Z_LIMIT):
        save_image(failure_path, renderer.image())
    assert np.all(np.abs(z) < Z_LIMIT), f"mean {mean} vs {expected}, z = {z}"
    assert renderer.nonfinite_samples == 0


def test_lossless_glass_sphere_in_emitter_converges_to_radiance(gpu_context, failure_dir):
    """Clear glass loses no energy and the eta^2 radiance scaling cancels on the way out, so every
    pixel's expectation is L. Russian roulette makes samples noisy but must not bias them: the
    image mean is z-tested against L with the standard error from the per-pixel spread."""
    spp = 16
    renderer = Renderer(glass_sphere_in_emitter(), SIZE, SIZE, seed=SEED, max_depth=UNLIMITED_DEPTH)
    renderer.render(spp)
    assert_mean_is(renderer, np.asarray(ENCLOSURE_RADIANCE), failure_dir / "glass_sphere_in_emitter.exr")


def test_zero_area_triangles_never_reach_the_gpu(gpu_context):
    """Collinear and repeated corners, in view inside the closed emitter: they are dropped with a
    warning naming the shape, so every pixel is still exactly L and no sample turns NaN."""
    corners = np.array([[0, 0, 0], [0.5, 0.5, 0], [1, 1, 0]], np.float32)  # on one line
    sliver = np.stack([corners, corners[[0, 0, 2]], corners[[1, 1, 1]]])
    shape = Shape("slivers", np.concatenate([sliver, sliver - 0.5]), Diffuse("grey"))
    with pytest.warns(
        DegenerateTrianglesWarning, match="dropped 6 zero-area triangles; the first is triangle 0 of shape 'slivers'"
    ):
        renderer = Renderer(inside_emitter(shape), SIZE, SIZE, seed=SEED, max_depth=9)
    renderer.render(2)
    np.testing.assert_allclose(renderer.image(), np.broadcast_to(ENCLOSURE_RADIANCE, (SIZE, SIZE, 3)), rtol=EXACT_RTOL)
    assert renderer.nonfinite_samples == 0
