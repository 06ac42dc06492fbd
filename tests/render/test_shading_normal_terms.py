"""What our shading normals add to Mitsuba's, on the scenes the `shading_normals` reference cases
compare without it: a smooth 80-triangle icosphere (`smooth_sphere`) and a normal-mapped plane
under a grazing light (`normal_mapped`).

The terminator term: a shading normal can tilt a facet towards a light its own plane barely faces;
without the term that facet goes black at once where the light passes its plane, a facet-shaped
step. Chiang et al. 2019's G' = G (1 + G - G^2), G = min(1, cos_g / (cos_s n_s.n_g)), bounds a
Lambertian facet's radiance by 1.25 / (n_s.n_g) times its flat version's. The smooth sphere and the
same sphere without its normals, under the point light alone: with the term every pixel keeps the
bound, without it pixels near the terminator break it (so the test can fail); the term only
darkens, by at most a tenth.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from wgputrace import DirectionalLight, Environment, Renderer
from wgputrace.kernels.shading_normals import SHADOW_TERMINATOR_TERM
from wgputrace.scene import Camera
from wgputrace.scenes.normal_mapped import (
    HALF_SIZE,
    LIGHT_ELEVATION_DEGREES,
    LIGHT_IRRADIANCE,
    SKY_RADIANCE,
    normal_mapped_plane,
)
from wgputrace.scenes.smooth_sphere import CENTRE_Y, RADIUS, smooth_sphere

pytestmark = pytest.mark.gpu

SEED = 20261208
SIZE = 64

# The direct-light comparison: camera and light samples only (a point light: no noise but the
# pixel's jitter, the same in both renders at one seed).
DIRECT_DEPTH = 2
DIRECT_SPP = 256
# G' <= 1.25 G: the largest of G (1 + G - G^2) / G over G in [0, 1] (at G = 1/2)
TERM_GAIN_MAX = 1.25
# Float32 roundings of two renders that agree sample for sample.
RADIANCE_ATOL = 1e-5
# The smooth sphere's radiance with the term over that without: measured 0.963.
DARKENING_MIN = 0.9


@cache
def direct_light(smooth: bool, term: bool) -> np.ndarray:
    """The red channel of the scene under its point light alone (no sky), `smooth` False with
    the upper sphere's normals dropped."""
    scene = smooth_sphere(smooth)
    scene.environment = None
    renderer = Renderer(
        scene, SIZE, SIZE, seed=SEED, max_depth=DIRECT_DEPTH, shader_overrides={SHADOW_TERMINATOR_TERM: term}
    )
    renderer.render(DIRECT_SPP)
    assert renderer.nonfinite_samples == 0
    return renderer.image()[..., 0]


def upper_sphere_pixels(fraction: float) -> np.ndarray:
    """The pixels whose centre ray meets the sphere of `fraction` x RADIUS about the upper
    sphere's centre: inside the mesh's silhouette for fractions below its inscribed radius."""
    camera = smooth_sphere().camera
    right, up, forward = camera.image_plane(SIZE, SIZE)
    ndc = (np.arange(SIZE) + 0.5) / SIZE * 2.0 - 1.0
    x, y = np.meshgrid(ndc, ndc)
    directions = forward + x[..., None] * right - y[..., None] * up
    directions /= np.linalg.norm(directions, axis=-1, keepdims=True)
    origin = np.asarray(camera.position) - np.array([0.0, CENTRE_Y, 0.0])
    b = directions @ origin
    return b * b - (origin @ origin - (fraction * RADIUS) ** 2) > 0.0


def smallest_normal_agreement() -> float:
    """The smallest n_s.n_g over the upper sphere's corners: how far a corner normal leans from its face."""
    shape = smooth_sphere().shapes[0]
    v = shape.world_vertices.astype(np.float64)
    face = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    return float(np.einsum("tcj,tj->tc", shape.world_normals, face).min())


@pytest.mark.slow
def test_terminator_term_fades_the_smooth_sphere_as_its_flat_version():
    # inside the inscribed sphere (an 80-triangle icosphere's is 0.79 of its radius): no silhouette
    inside = upper_sphere_pixels(0.75)
    flat = direct_light(smooth=False, term=True)[inside]
    bound = TERM_GAIN_MAX / smallest_normal_agreement() * flat + RADIANCE_ATOL
    with_term, without_term = direct_light(True, True)[inside], direct_light(True, False)[inside]
    assert (with_term <= bound).all(), f"{(with_term > bound).sum()} pixels brighter than the flat facets allow"
    assert (without_term > bound).sum() >= 10  # measured 23 of 354: the steps the term removes
    assert (with_term <= without_term + RADIANCE_ATOL).all()
    assert with_term.sum() >= DARKENING_MIN * without_term.sum()


def plane_pixels(scene) -> np.ndarray:
    """The pixels whose centre ray meets the normal-mapped plane (z = 0, |x|, |y| < HALF_SIZE)."""
    camera = scene.camera
    right, up, forward = camera.image_plane(SIZE, SIZE)
    ndc = (np.arange(SIZE) + 0.5) / SIZE * 2.0 - 1.0
    x, y = np.meshgrid(ndc, ndc)
    directions = forward + x[..., None] * right - y[..., None] * up
    t = -camera.position[2] / directions[..., 2]
    hit = np.asarray(camera.position) + t[..., None] * directions
    return (t > 0) & (np.abs(hit[..., :2]) < HALF_SIZE).all(axis=-1)


@pytest.mark.slow
def test_bumps_under_a_grazing_light_leak_nothing_and_see_no_black_directions():
    """The bumps tilt 28 degrees, further than the light's 10: a light that far behind the plane is
    above many bumps' shading horizon, and must still light nothing in front (pbrt's side rule);
    a view that grazes the plane (5 degrees) under the sky alone sees no black point on it (a
    mapped normal that hides the viewer falls back to the geometric one)."""
    behind = normal_mapped_plane()
    behind.environment = None
    (light,) = behind.lights
    behind.remove_light(light)
    elevation = np.radians(LIGHT_ELEVATION_DEGREES)
    behind.add_light(DirectionalLight((-np.cos(elevation), 0.0, np.sin(elevation)), LIGHT_IRRADIANCE))
    grazing = normal_mapped_plane()
    grazing.remove_light(*grazing.lights)
    grazing.environment = Environment(radiance=SKY_RADIANCE, visible=False)
    view = np.radians(5.0)
    grazing.camera = Camera.looking_at((0.0, -3.0 * np.cos(view), 3.0 * np.sin(view)), (0, 0, 0), vfov_degrees=20.0)
    images = {}
    for name, scene in (("behind", behind), ("grazing", grazing)):
        renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=DIRECT_DEPTH)
        renderer.render(16)
        assert renderer.nonfinite_samples == 0
        images[name] = renderer.image()
    assert (images["behind"] == 0.0).all()
    seen = plane_pixels(grazing)
    assert seen.sum() > SIZE  # the plane fills a band of the picture
    assert (images["grazing"][seen] > 0.0).all()
