"""Closed forms for the lights whose kinds' tests render none (those have the constant-environment
furnace and a plane under a directional and a point light): a plane under a sun, the sun's disc
seen directly, a spot light's footprint on a plane, and the environment map's direction convention
pinned by a map black but for one texel.

Each rendered expectation is tested by Welch's t-test (`compare_blocks`) against the
exact value, its variance from K independent batches; the significance of each test is Sidak's
share of FAMILY_SIGNIFICANCE over every test of this module."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Renderer, Scene, Shape, SpotLight, Sun, make_plane
from wgputrace.scene.lights.environment import Environment
from wgputrace.scenes.environment_lit import ONE_TEXEL_ROTATION_DEGREES, one_texel_map, one_texel_uv
from wgputrace.testing.image_statistics import Estimate, compare_blocks
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SEED = 15
FAMILY_SIGNIFICANCE = 1e-3
INTEGRATORS = ("bsdf", "nee", "mis", "bdpt")
ALBEDO = 0.5
BATCHES = 8
# f32 shading against float64 closed forms: a few roundings per sample, never averaged away
RTOL = 1e-5

# Welch tests: sun plane (3 integrators), spot footprint (SPOT_BLOCKS blocks + the whole image),
# the one-texel map's lit plane (3 integrators); 3 channels each
SPOT_SIZE, SPOT_BLOCK = 32, 8
SPOT_BLOCKS = (SPOT_SIZE // SPOT_BLOCK) ** 2
LEVEL = sidak(FAMILY_SIGNIFICANCE, 3 * (len(INTEGRATORS) + SPOT_BLOCKS + 1 + len(INTEGRATORS)))


def batches(scene: Scene, size: int, spp: int, integrator: str = "mis", max_depth: int = 2) -> np.ndarray:
    """(BATCHES, size, size, 3) independent images, none with a non-finite sample."""
    renderer = Renderer(scene, size, size, seed=SEED, max_depth=max_depth, integrator=integrator)
    images = []
    for _ in range(BATCHES):
        renderer.render(spp)
        images.append(renderer.image())
        assert renderer.nonfinite_samples == 0
        renderer.reset()
    return np.stack(images)


def assert_expectation(label: str, images: np.ndarray, expected: np.ndarray, block: int, tolerance=0.0) -> None:
    """Every block's mean of `images` (batches) has the expectation `expected` (exact, per pixel),
    up to `tolerance` per block (what the closed form's own quadrature may be off by)."""
    exact = Estimate(np.broadcast_to(expected, images.shape[1:]).astype(np.float64), np.zeros(images.shape[1:]), np.inf)
    comparison = compare_blocks(Estimate.from_batches(images), exact, block, tolerance)
    worst = np.unravel_index(np.argmin(comparison.p_value), comparison.p_value.shape)
    assert comparison.p_value.min() >= LEVEL, (
        f"{label}: block (row, column) {tuple(int(i) for i in worst[:2])} channel {'rgb'[worst[2]]} differs from the closed form by "
        f"{comparison.difference[worst]:.4g} (z {comparison.z[worst]:.2f}, p {comparison.p_value[worst]:.2g} < {LEVEL:.2g})"
    )


def facing(normal, size: float = 1.0) -> Shape:
    """A diffuse square of side `size` through the origin, wound to face `normal`."""
    normal = np.asarray(normal, np.float64) / np.linalg.norm(normal)
    side = np.cross(normal, (0.0, 1.0, 0.0) if abs(normal[1]) < 0.9 else (1.0, 0.0, 0.0))
    side /= np.linalg.norm(side)
    other = np.cross(normal, side)
    a, b, c, d = (size / 2 * (s * side + t * other) for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1)))
    triangles = np.array([[a, b, c], [a, c, d]])
    return Shape("square", triangles, Diffuse("square", (ALBEDO,) * 3))


def looking_at_it(normal, distance: float, vfov_degrees: float) -> Camera:
    normal = np.asarray(normal, np.float64) / np.linalg.norm(normal)
    up = (0.0, 1.0, 0.0) if abs(normal[1]) < 0.9 else (1.0, 0.0, 0.0)
    return Camera(position=tuple(distance * normal), forward=tuple(-normal), up=up, vfov_degrees=vfov_degrees)


# ---- the sun


SUN_IRRADIANCE = 3.0
SUN_ZENITH_DEGREES = 40.0
# wide enough that BSDF sampling alone finds it (0.024 sr)
SUN_DIAMETER_DEGREES = 10.0


def sun() -> Sun:
    angle = math.radians(SUN_ZENITH_DEGREES)
    return Sun((math.sin(angle), -math.cos(angle), 0.0), SUN_IRRADIANCE, angular_diameter_degrees=SUN_DIAMETER_DEGREES)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_plane_under_a_sun_has_radiance_albedo_irradiance_cos_over_pi(gpu_context, integrator):
    # the disc (uniform radiance) lies wholly above the horizon: its L cos integrates to E cos(theta)
    scene = Scene([facing((0, 1, 0), 4.0)], looking_at_it((0, 1, 0), 3.0, 30.0))
    scene.add_light(sun())
    images = batches(scene, 16, {"bsdf": 64, "nee": 4, "mis": 4, "bdpt": 4}[integrator], integrator)
    expected = ALBEDO * SUN_IRRADIANCE * math.cos(math.radians(SUN_ZENITH_DEGREES)) / math.pi
    assert_expectation(f"sun on a plane, {integrator}", images, expected, 16, RTOL * expected)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_the_suns_disc_seen_directly_has_radiance_e_over_pi_sin2(gpu_context, integrator):
    light = sun()
    # looking into the disc (half-angle 5 degrees): the picture's corners are 2.9 degrees off its axis
    behind = make_plane((0, 0, 0), (0, 0, 0), (1, 1), Diffuse("floor"))
    scene = Scene([behind], Camera(position=(0, 1, 0), forward=tuple(-np.asarray(light.direction)), vfov_degrees=4.0))
    scene.add_light(light)
    renderer = Renderer(scene, 8, 8, seed=SEED, max_depth=2, integrator=integrator)
    renderer.render(2)
    radiance = SUN_IRRADIANCE / (math.pi * math.sin(math.radians(SUN_DIAMETER_DEGREES / 2)) ** 2)
    np.testing.assert_allclose(renderer.image(), radiance, rtol=RTOL)


# ---- the spot light's footprint


SPOT_HEIGHT, SPOT_INTENSITY, SPOT_CUTOFF, SPOT_BEAM = 2.0, 4.0, 30.0, 15.0
SPOT_CAMERA_HEIGHT, SPOT_VFOV = 5.0, 36.0
# sub-pixel positions per axis of the closed form's midpoint quadrature over each pixel (box filter)
SPOT_QUADRATURE = 16


def spot_radiance(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """A diffuse floor's radiance at (x, 0, z) under the spot SPOT_HEIGHT above the origin, looking
    down: albedo / pi x I falloff(angle) cos / d^2, falloff Mitsuba's (1 within the beam, linear in
    angle to 0 at the cutoff)."""
    d2 = x * x + z * z + SPOT_HEIGHT**2
    cos = SPOT_HEIGHT / np.sqrt(d2)
    angle = np.arccos(cos)
    cutoff, beam = math.radians(SPOT_CUTOFF), math.radians(SPOT_BEAM)
    falloff = np.clip((cutoff - angle) / (cutoff - beam), 0.0, 1.0)
    return ALBEDO / math.pi * SPOT_INTENSITY * falloff * cos / d2


def spot_pixels(camera: Camera, size: int, quadrature: int) -> np.ndarray:
    """(size, size) mean floor radiance over each pixel, by the camera's own ray model
    (WGSL `camera_ray`: ndc from the pixel's jittered position, row 0 at the top)."""
    right, up, forward = camera.image_plane(size, size)
    offsets = (np.arange(quadrature) + 0.5) / quadrature
    positions = (np.arange(size)[:, None] + offsets[None, :]).ravel() / size * 2.0 - 1.0
    ndc_y, ndc_x = np.meshgrid(positions, positions, indexing="ij")
    directions = forward + ndc_x[..., None] * right - ndc_y[..., None] * up
    t = -camera.position[1] / directions[..., 1]
    hits = np.asarray(camera.position) + t[..., None] * directions
    radiance = spot_radiance(hits[..., 0], hits[..., 2])
    return radiance.reshape(size, quadrature, size, quadrature).mean(axis=(1, 3))


def test_spot_light_footprint_on_a_plane(gpu_context):
    scene = Scene([facing((0, 1, 0), 8.0)], looking_at_it((0, 1, 0), SPOT_CAMERA_HEIGHT, SPOT_VFOV))
    scene.add_light(SpotLight((0, SPOT_HEIGHT, 0), (0, -1, 0), SPOT_INTENSITY, SPOT_CUTOFF, SPOT_BEAM))
    images = batches(scene, SPOT_SIZE, 16)
    expected = spot_pixels(scene.camera, SPOT_SIZE, SPOT_QUADRATURE)[..., None]
    # the quadrature's error, bounded by its change from half as many points, summed over a block
    coarse = spot_pixels(scene.camera, SPOT_SIZE, SPOT_QUADRATURE // 2)[..., None]
    error = np.abs(expected - coarse) + RTOL * expected
    outside = expected[..., 0] == 0.0
    assert outside.any() and (expected[..., 0] > 0).any(), "the picture shows the footprint's edge"
    assert np.all(images[:, outside] == 0.0), "no light beyond the cutoff"
    for block in (SPOT_BLOCK, SPOT_SIZE):
        blocks = error.reshape(SPOT_SIZE // block, block, SPOT_SIZE // block, block, 1).mean(axis=(1, 3))
        assert_expectation(f"spot footprint, {block}x{block} blocks", images, expected, block, blocks)


# ---- the environment map's direction convention


# the closed form's quadrature over the sphere: (u, v) midpoints
CONVENTION_QUADRATURE = (512, 256)


def one_texel_environment() -> Environment:
    return Environment(texels=one_texel_map(), rotation_degrees=ONE_TEXEL_ROTATION_DEGREES)


def lit_plane_radiance(environment: Environment, normal: np.ndarray, resolution: tuple[int, int]) -> float:
    """albedo / pi x the integral over the sphere of L(w) max(0, n.w): a diffuse plane's radiance."""
    columns, rows = resolution
    u, v = (np.arange(columns) + 0.5) / columns, (np.arange(rows) + 0.5) / rows
    uv = np.stack(np.meshgrid(u, v), axis=-1).reshape(-1, 2)
    directions = environment.direction(uv)
    radiance = environment.lookup(directions)[:, 0]
    solid_angle = 2.0 * math.pi**2 * np.sin(math.pi * uv[:, 1]) / (columns * rows)
    return ALBEDO / math.pi * float(np.sum(radiance * np.maximum(directions @ normal, 0.0) * solid_angle))


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_one_bright_texel_lights_the_side_facing_its_documented_direction(gpu_context, integrator):
    environment = one_texel_environment()
    toward = environment.direction(one_texel_uv())[0]
    expected = lit_plane_radiance(environment, toward, CONVENTION_QUADRATURE)
    coarse = lit_plane_radiance(environment, toward, tuple(n // 2 for n in CONVENTION_QUADRATURE))
    # the texel's light reaches at most 45 degrees from its direction: all of it in front
    assert expected > 0.1 and lit_plane_radiance(environment, -toward, CONVENTION_QUADRATURE) == 0.0

    def render_facing(normal: np.ndarray) -> np.ndarray:
        scene = Scene([facing(normal)], looking_at_it(normal, 3.0, 5.0))
        scene.environment = environment
        return batches(scene, 8, {"bsdf": 32, "nee": 8, "mis": 8, "bdpt": 8}[integrator], integrator)

    tolerance = abs(expected - coarse) + RTOL * expected
    assert_expectation(f"plane facing the texel, {integrator}", render_facing(toward), expected, 8, tolerance)
    assert np.all(render_facing(-toward) == 0.0), f"{integrator}: a plane facing away from the texel is lit"
