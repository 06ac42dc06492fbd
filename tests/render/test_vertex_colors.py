"""Vertex colours on the GPU: a white diffuse triangle with red, green and blue corners inside an
enclosure of uniform radiance L returns L times the colour interpolated at each hit (one bounce: the
triangle sees only the enclosure), which every integrator must reproduce; a MASK material cuts out
where the interpolated vertex alpha falls below its cutoff; scenes without colours bind nothing
for them."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Principled, Renderer, Shape, save_image
from wgputrace.gpu.layout import VERTEX_COLOR
from wgputrace.render.scene_mirror import VERTEX_COLORS
from wgputrace.scene import cornell_box
from wgputrace.testing.camera_rays import camera_rays
from wgputrace.testing.scenes import ENCLOSURE_RADIANCE, inside_emitter
from wgputrace.testing.stats import sidak, z_limit

pytestmark = pytest.mark.gpu

SEED = 20_261_203
SIZE = 32
SPP = 64
# the three integrators: the path tracer by BSDF sampling alone (every sample of a hit is exactly
# L x colour) and with light sampling (MIS), and bidirectional (light paths hit the triangle too)
INTEGRATORS = ("bsdf", "mis", "bdpt")
# Pixels are compared in square blocks of this side, each block's mean difference z-tested with the
# standard error of its pixels (independent samples); blocks with fewer covered pixels are skipped.
BLOCK = 4
MIN_BLOCK_PIXELS = 8
SIGNIFICANCE = 1e-3
# float32 along a path and in the accumulation: the difference allowed where a block has no variance
FLOAT_TOLERANCE = 1e-5
# Camera rays per pixel over which the expected colour is averaged: the colour is linear on the
# triangle, so the midpoint rule over the pixel is exact up to the perspective's curvature.
SUBPIXELS = 4
# a triangle in z = 0 facing the camera at z = -2 (inside_emitter's), inside the 40 degree view
TRIANGLE = np.array([[(-0.6, -0.5, 0.0), (0.0, 0.6, 0.0), (0.6, -0.5, 0.0)]], np.float32)
RGB_CORNERS = np.array([[(1, 0, 0, 1), (0, 1, 0, 1), (0, 0, 1, 1)]], np.float32)


def colored_triangle(material, colors: np.ndarray) -> Shape:
    return Shape("triangle", TRIANGLE, material, colors=colors)


def expected_colors(scene, colors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vertex colour (RGBA) averaged over SUBPIXELS^2 camera rays of each pixel (SIZE, SIZE, 4),
    and which pixels lie wholly on the triangle (SIZE, SIZE)."""
    offsets = (np.arange(SUBPIXELS) + 0.5) / SUBPIXELS
    rows, columns, dy, dx = np.meshgrid(np.arange(SIZE), np.arange(SIZE), offsets, offsets, indexing="ij")
    pixels = np.stack([columns.ravel(), rows.ravel()], axis=1)
    jitter = np.stack([dx.ravel(), dy.ravel()], axis=1)
    origins, directions = camera_rays(scene.camera, SIZE, SIZE, pixels, jitter, np.zeros_like(jitter))
    v0, v1, v2 = TRIANGLE[0].astype(np.float64)
    hits = origins - (origins[:, 2:] - v0[2]) / directions[:, 2:] * directions
    # barycentric weights of v1 and v2 in the triangle's plane (z = 0)
    e = np.stack([v1 - v0, v2 - v0], axis=1)[:2]
    b = np.linalg.solve(e, (hits - v0)[:, :2].T).T
    weights = np.concatenate([1.0 - b.sum(axis=1, keepdims=True), b], axis=1)
    inside = (weights >= 0.0).all(axis=1).reshape(SIZE, SIZE, -1).all(axis=-1)
    color = (weights @ colors[0].astype(np.float64)).reshape(SIZE, SIZE, SUBPIXELS**2, 4).mean(axis=2)
    return color, inside


def block_z_scores(difference: np.ndarray, covered: np.ndarray) -> np.ndarray:
    """|mean| / standard error of `difference` (SIZE, SIZE) over the covered pixels of each BLOCK
    square, for blocks with at least MIN_BLOCK_PIXELS of them."""
    scores = []
    for top in range(0, SIZE, BLOCK):
        for left in range(0, SIZE, BLOCK):
            values = difference[top : top + BLOCK, left : left + BLOCK][covered[top : top + BLOCK, left : left + BLOCK]]
            if values.size >= MIN_BLOCK_PIXELS:
                error = values.std(ddof=1) / np.sqrt(values.size)
                scores.append(max(abs(values.mean()) - FLOAT_TOLERANCE, 0.0) / max(error, FLOAT_TOLERANCE))
    return np.array(scores)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_vertex_colours_interpolate_across_a_white_diffuse_triangle(failure_dir, integrator):
    scene = inside_emitter(colored_triangle(Diffuse("white", color=(1, 1, 1)), RGB_CORNERS))
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator=integrator)
    assert "vertex colours" in renderer.variant.label
    renderer.render(SPP)
    image = renderer.image().astype(np.float64) / np.asarray(ENCLOSURE_RADIANCE)
    expected, covered = expected_colors(scene, RGB_CORNERS)
    scores = np.concatenate([block_z_scores(image[..., c] - expected[..., c], covered) for c in range(3)])
    limit = z_limit(sidak(SIGNIFICANCE / len(INTEGRATORS), scores.size))
    if scores.max() > limit:
        save_image(failure_dir / f"vertex_colors_{integrator}_image.png", image)
        save_image(failure_dir / f"vertex_colors_{integrator}_expected.png", expected[..., :3])
    assert covered.sum() > SIZE * SIZE / 8 and scores.size > 3 * 8
    assert scores.max() <= limit, (
        f"{integrator}: a block's mean differs from L x the interpolated colour by {scores.max():.1f} standard "
        f"errors (limit {limit:.2f}); images in {failure_dir}"
    )
    assert renderer.nonfinite_samples == 0


def test_vertex_alpha_cuts_out_a_masked_surface_where_it_falls_below_the_cutoff():
    # alpha 1 at the top corner, 0 at the bottom ones: MASK at 0.5 keeps the part above the middle
    colors = np.ones_like(RGB_CORNERS)
    colors[0, [0, 2], 3] = 0.0
    material = Principled("cut", base_color=(1, 1, 1), roughness=1.0, alpha_mode="MASK", alpha_cutoff=0.5)
    scene = inside_emitter(colored_triangle(material, colors))
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=1, integrator="bsdf")
    renderer.render(1)
    # at max depth 1 the enclosure is L and the triangle, not emitting, black
    image = renderer.image()[..., 0] / ENCLOSURE_RADIANCE[0]
    alpha, covered = expected_colors(scene, colors)
    kept, cut = covered & (alpha[..., 3] > 0.6), covered & (alpha[..., 3] < 0.4)
    assert kept.sum() > 20 and cut.sum() > 20
    np.testing.assert_allclose(image[kept], 0.0, atol=1e-6)
    np.testing.assert_allclose(image[cut], 1.0, rtol=1e-5)


def test_scenes_without_vertex_colours_compile_and_bind_none():
    plain = Renderer(cornell_box(), 8, 8, seed=SEED)
    assert "vertex colours" not in plain.variant.label and VERTEX_COLORS not in plain.gpu_scene_bytes
    scene = cornell_box()
    shape = scene.shapes[0]
    shape.colors = np.ones((shape.triangle_count, 3, 4), np.float32)
    colored = Renderer(scene, 8, 8, seed=SEED)
    assert "vertex colours" in colored.variant.label
    # an RGBA float per vertex, spare rows aside: every corner of the cornell box shares its one white
    vertex_count = len(colored.records.vertices[VERTEX_COLORS])
    assert vertex_count == 1 and colored.gpu_scene_bytes[VERTEX_COLORS] >= VERTEX_COLOR.size * vertex_count
    shape.colors = None  # the edit rebuilds without them
    colored.render(1)
    assert "vertex colours" not in colored.variant.label and VERTEX_COLORS not in colored.gpu_scene_bytes
