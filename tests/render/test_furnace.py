"""White furnace: each non-emitting material of colour 1 inside a closed emitter of uniform radiance L
(`inside_emitter`) returns L times what it keeps of the light. That is L exactly for diffuse and for
lossless glass (every path ends on the emitter; the eta^2 scaling cancels on the way out, so a
wrong one goes unseen here: the BSDF sampling tests check it). Single-scattering GGX loses what its
microfacets would reflect a second time: one bounce off a plane at a fixed angle must return its
directional albedo A(wi), the shipped bsdf_eval integrated on the GPU (`integrate_bsdf`). Image means
are z-tested with the standard error of their pixels, which are independent samples."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import UNLIMITED_DEPTH, Camera, Diffuse, Glass, Glossy, Renderer, Scene, make_box, make_plane, save_image
from wgputrace.render.scene_records import material_records
from wgputrace.testing.bsdf_grid import EVAL, integrate_bsdf, lobe_grid
from wgputrace.testing.scenes import ENCLOSURE_RADIANCE, inside_emitter
from wgputrace.testing.stats import sidak, z_limit

pytestmark = [pytest.mark.gpu, pytest.mark.slow]

# Each render's seed: SEED plus the case's index, so that no two renders share random numbers.
SEED = 9
SIZE = 32
# Samples per pixel: 32 x 32 x 64 samples leave standard errors of at most 1.5e-3 L (glossy 0.5),
# so an energy error of 0.6% of L fails (4.1 standard errors).
SPP = 64
# Probability that any test of this file fails by chance though the renderer is right: Sidak-split.
SIGNIFICANCE = 1e-3
# Float32 arithmetic along a path and in the Kahan-compensated sum: a few roundings of 2^-24
# each. Where a case has no variance (diffuse under BSDF sampling: every sample is exactly L),
# this is all the difference allowed.
FLOAT_RTOL = 1e-5
# The expected value is computed (quadrature, interpolation over the pixels' angles) to within
# this fraction of the standard error: it moves z by at most this much.
INTEGRATION_FRACTION = 0.1
# A(cos theta) is computed at this many Chebyshev nodes spanning the image's angles and
# interpolated; the parabola through three of them bounds the error.
ALBEDO_NODES = 5
# Camera rays per pixel, uniform like the renderer's jitter, over which A is averaged.
SUBPIXELS = 4

# The plane at the origin, turned so the camera, 2 units away, sees it at these cosines through
# a field of view this narrow: across the image cos theta varies by at most ~0.02.
INCIDENT_COSINES = (1.0, 0.5, 0.1)
VFOV_DEGREES = 1.0
PLANE_SIZE = 4.0

DIFFUSE = Diffuse("diffuse", color=(1, 1, 1))
GLOSSY = [Glossy(f"glossy {r}", color=(1, 1, 1), roughness=r) for r in (0.01, 0.1, 0.5, 1.0)]
# BSDF sampling alone tests the samples' weights; MIS (the default) adds light samples weighted
# by bsdf_pdf, the enclosure being the light (glossy below GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS
# samples no lights: MIS is BSDF sampling there); bidirectional path tracing
# adds light paths from the enclosure, connected and traced to the camera. Diffuse keeps A = 1 at
# every angle, so one suffices.
INTEGRATORS = ("bsdf", "mis")
REFLECTION_CASES = [(DIFFUSE, 0.5, i) for i in INTEGRATORS] + [
    (m, c, i) for m in GLOSSY for c in INCIDENT_COSINES for i in INTEGRATORS
]
# bidirectional path tracing on a diffuse and a glossy plane (a few seconds each)
REFLECTION_CASES += [(DIFFUSE, 0.5, "bdpt"), (GLOSSY[1], 0.5, "bdpt")]
# restir resamples the first vertex's light candidates and weighs what its BSDF sample finds
# against them by MIS, with its own and (restir-shared) its neighbours' reservoirs: a weight that
# does not sum to one with the BSDF's shows here as light gained or lost. Last, so that the cases
# before keep their seeds.
# Diffuse, and two roughnesses seen head on: where the BSDF's samples take much of the light (0.1)
# and where the reservoir does (0.5), for CI time.
RESAMPLING = ("restir", "restir-shared")
REFLECTION_CASES += [(m, c, i) for m, c in ((DIFFUSE, 0.5), (GLOSSY[1], 1.0), (GLOSSY[2], 1.0)) for i in RESAMPLING]
# the integrator and shader overrides behind each name above
INTEGRATOR_VARIANTS = {"restir-shared": ("restir", {"RESERVOIR_NEIGHBOURS": 3})}
# Glass in a tilted cube: a ray that entered through one face meets the side faces beyond the
# critical angle and leaves through the opposite one, so paths stay short. (In a faceted sphere,
# rays can circle by total internal reflection with the facets tilting them at random; Russian
# roulette, whose survival is capped at 0.95, then gives the survivors weights growing as
# 0.95^-bounces: the mean is right but so heavy-tailed that a z-test with the sample's standard
# error fails far more often than its level says.)
GLASS_IORS = (1.33, 1.51714, 2.4)
CUBE_SIZE = 1.6  # at the origin, 2 from the camera: it fills most of the 40 degree view
Z_LIMIT = z_limit(sidak(SIGNIFICANCE, len(REFLECTION_CASES) + len(GLASS_IORS)))


def plane_facing_camera(material, cos_theta: float) -> Scene:
    """The plane tilted about x so its normal makes angle acos(cos_theta) with the view axis."""
    # the unit plane's normal +y, turned by rx about x, is (0, cos rx, sin rx)
    rx = np.arccos(cos_theta) - np.pi / 2
    plane = make_plane((0, 0, 0), (rx, 0, 0), (PLANE_SIZE, PLANE_SIZE), material, "plane")
    camera = Camera(position=(0, 0, -2), forward=(0, 0, 1), up=(0, 1, 0), vfov_degrees=VFOV_DEGREES)
    return Scene(inside_emitter(plane).shapes, camera)


def pixel_cosines(scene: Scene) -> np.ndarray:
    """|cos theta| at the plane of camera rays through SUBPIXELS^2 points of each pixel
    (SIZE, SIZE, SUBPIXELS^2), as WGSL `camera_ray` builds them (row 0 at the top)."""
    right, up, forward = scene.camera.image_plane(SIZE, SIZE)
    offsets = (np.arange(SUBPIXELS) + 0.5) / SUBPIXELS
    x = ((np.arange(SIZE)[:, None] + offsets) / SIZE * 2.0 - 1.0).ravel()
    ndc_x, ndc_y = np.meshgrid(x, x)
    directions = forward + ndc_x[..., None] * right - ndc_y[..., None] * up
    triangle = scene.shapes[-1].vertices[0].astype(np.float64)
    normal = np.cross(triangle[1] - triangle[0], triangle[2] - triangle[0])
    cosines = np.abs(directions @ normal) / np.linalg.norm(directions, axis=-1) / np.linalg.norm(normal)
    blocks = cosines.reshape(SIZE, SUBPIXELS, SIZE, SUBPIXELS).transpose(0, 2, 1, 3)
    return blocks.reshape(SIZE, SIZE, SUBPIXELS * SUBPIXELS)


def albedo_budget(integrals: np.ndarray, tolerance: float) -> np.ndarray:
    """Quadrature error each cell may have for the sum to stay within `tolerance`: half shared
    in proportion to the cells' values (float32 evaluations put a floor under each cell's
    relative error), half evenly."""
    total = max(integrals.sum(), np.finfo(np.float64).tiny)
    return 0.5 * tolerance * (np.abs(integrals) / total + 1.0 / integrals.size)


def albedo(context, material, cosines: np.ndarray, tolerance: float) -> tuple[np.ndarray, float]:
    """A(wi) of the shipped bsdf_eval at every cosine of `cosines`, interpolated from
    ALBEDO_NODES Chebyshev nodes spanning them, and a bound on the error."""
    lo, hi = cosines.min(), cosines.max()
    nodes = 0.5 * (lo + hi) + 0.5 * (hi - lo) * np.cos(np.pi * (np.arange(ALBEDO_NODES) + 0.5) / ALBEDO_NODES)
    wi = np.stack([np.sqrt(1.0 - nodes**2), np.zeros_like(nodes), nodes], axis=1).astype(np.float32)
    grids = [lobe_grid(material, w) for w in wi]
    records = np.repeat(material_records([material]), len(wi))
    integrals = integrate_bsdf(context, records, wi, grids, EVAL, lambda values: albedo_budget(values, tolerance))
    value = integrals.value.sum(axis=(1, 2))
    span = max(hi - lo, np.finfo(np.float64).tiny)
    fine = np.polynomial.Chebyshev.fit(nodes, value, ALBEDO_NODES - 1, domain=[lo - span, hi + span])
    coarse = np.polynomial.Chebyshev.fit(nodes[::2], value[::2], 2, domain=[lo - span, hi + span])
    error = integrals.error.sum(axis=(1, 2)).max() + np.max(np.abs(fine(cosines) - coarse(cosines)))
    return fine(cosines), error


def assert_image_mean(renderer: Renderer, expected: np.ndarray, error: float, failure_dir, name: str) -> None:
    """z-test of the mean over pixels of image / L - expected (SIZE, SIZE), allowing `error` in
    the expectation and FLOAT_RTOL of rounding."""
    image = renderer.image().astype(np.float64) / np.asarray(ENCLOSURE_RADIANCE)
    # color 1 everywhere: the three channels carry the same samples, scaled by L
    assert np.allclose(image, image[..., :1], rtol=FLOAT_RTOL), f"{name}: channels differ after dividing by L"
    difference = image[..., 0] - expected
    mean = difference.mean()
    standard_error = difference.std(ddof=1) / np.sqrt(difference.size)
    assert error <= INTEGRATION_FRACTION * max(standard_error, FLOAT_RTOL), (
        f"{name}: expected value known only to {error:.2g}, standard error {standard_error:.2g}"
    )
    bound = Z_LIMIT * standard_error + FLOAT_RTOL * np.abs(expected).mean()
    if abs(mean) > bound:
        # image and expectation at half brightness (1 is mid grey), the difference around 0.5 in
        # units of 8 pixel standard deviations
        spread = max(difference.std(ddof=1), FLOAT_RTOL)
        for suffix, picture in (
            ("image", image[..., 0] / 2),
            ("expected", expected / 2),
            ("difference", 0.5 + difference / (8 * spread)),
        ):
            save_image(failure_dir / f"furnace_{name}_{suffix}.png", np.repeat(picture[..., None], 3, axis=-1))
    assert abs(mean) <= bound, (
        f"{name}: image / L - expected has mean {mean:.3g}, beyond {bound:.3g} "
        f"({Z_LIMIT:.2f} standard errors of {standard_error:.2g}); images in {failure_dir}"
    )
    assert renderer.nonfinite_samples == 0, f"{name}: {renderer.nonfinite_samples} non-finite samples"


def case_id(case) -> str:
    material, cos_theta, integrator = case
    return f"{material.name}, cos {cos_theta:g}, {integrator}"


@pytest.mark.parametrize("index", range(len(REFLECTION_CASES)), ids=[case_id(c) for c in REFLECTION_CASES])
def test_reflector_returns_its_albedo(gpu_context, failure_dir, index):
    material, cos_theta, integrator = REFLECTION_CASES[index]
    scene = plane_facing_camera(material, cos_theta)
    integrator, overrides = INTEGRATOR_VARIANTS.get(integrator, (integrator, {}))
    renderer = Renderer(
        scene, SIZE, SIZE, seed=SEED + index, max_depth=2, integrator=integrator, shader_overrides=overrides
    )
    renderer.render(SPP)
    # the tolerance for quadrature: a fraction of the standard error, itself known only after
    # rendering; a lossless case (diffuse) needs only float accuracy
    image = renderer.image()[..., 0] / ENCLOSURE_RADIANCE[0]
    tolerance = 0.5 * INTEGRATION_FRACTION * max(image.std(ddof=1) / SIZE, FLOAT_RTOL)
    cosines = pixel_cosines(scene)
    values, error = albedo(gpu_context, material, cosines, tolerance)
    name = case_id(REFLECTION_CASES[index]).replace(", ", "_").replace(" ", "")
    assert_image_mean(renderer, values.mean(axis=-1), error, failure_dir, name)


@pytest.mark.parametrize("index", range(len(GLASS_IORS)), ids=[f"ior {n}" for n in GLASS_IORS])
def test_lossless_glass_returns_the_radiance(gpu_context, failure_dir, index):
    ior = GLASS_IORS[index]
    glass = Glass("glass", color=(1, 1, 1), ior=ior)
    cube = make_box((0, 0, 0), (0.3, 0.5, 0.1), (CUBE_SIZE,) * 3, glass, "cube")
    seed = SEED + len(REFLECTION_CASES) + index
    renderer = Renderer(inside_emitter(cube), SIZE, SIZE, seed=seed, max_depth=UNLIMITED_DEPTH)
    renderer.render(SPP)
    assert_image_mean(renderer, np.ones((SIZE, SIZE)), 0.0, failure_dir, f"glass_cube_{ior}")
