"""The shipped 4-wide traversal (shaders/traverse_bvh.wgsl) finds what the binary traversal it
replaced finds (bench/kernel_variants/binary_nodes.py, kept for kernel_profile's A/B).

Both are tested against float64 brute force (the shipped one in tests/shaders/test_traversal.py);
they run the same box and triangle arithmetic in another order, so they must return the very same
closest distances, bit for bit, except that of triangles hit at exactly the same distance either
may pick another, and the very same occlusion answers.
"""

from __future__ import annotations

import numpy as np
import pytest

from bench.kernel_variants.binary_nodes import binary_traversal_wgsl
from bench.traversal_ceiling import pixel_centre_rays
from tests.bvh.test_wide import SHALLOW_DEPTH, soup
from tests.harness import run_kernel
from tests.shaders.reference import as_vec4, unit_vectors
from wgputrace import default_scene
from wgputrace.bvh import build_bvh
from wgputrace.bvh.wide import BUILD_MAX_DEPTH, collapse
from wgputrace.gpu.pipeline import NO_TRIANGLE
from wgputrace.gpu.texels import TrackedTexels
from wgputrace.render.scene_buffers import node_records, scene_records, triangle_records, wide_node_records

pytestmark = pytest.mark.gpu

RAY_COUNT = 3_000
CAMERA_RAYS_SIZE = 64  # square image of pixel-centre camera rays on the Cornell box

# Per ray: closest hit (t, triangle) and whether anything lies before the distance in inputs_0.w.
KERNEL = """
{traversal}
fn compute(i: u32) -> vec4<f32> {{
    let ray = Ray(inputs_0[i].xyz, inputs_1[i].xyz);
    let hit = closest_hit(ray, FLOAT_MAX, NO_TRIANGLE);
    let blocked = occluded(ray, inputs_0[i].w, NO_TRIANGLE);
    return vec4<f32>(hit.t, bitcast<f32>(hit.triangle), select(0.0, 1.0, blocked), 0.0);
}}
"""
SHIPPED = '//! include "traverse_bvh.wgsl"'


def hits(context, traversal: str, triangles: np.ndarray, nodes, rays: tuple[np.ndarray, ...]) -> np.ndarray:
    origins, directions, occlusion_distance = rays
    inputs = as_vec4(origins)
    inputs[:, 3] = occlusion_distance
    return run_kernel(
        context,
        KERNEL.format(traversal=traversal),
        [inputs, as_vec4(directions)],
        np.dtype((np.float32, 4)),
        len(origins),
        input_types=["vec4<f32>", "vec4<f32>"],
        output_type="vec4<f32>",
        scene={1: triangles, 2: nodes},
    )


def assert_shipped_finds_what_binary_finds(context, triangles: np.ndarray, bvh, rays: tuple[np.ndarray, ...]) -> None:
    wide_nodes = TrackedTexels(context, "wide nodes", wide_node_records(collapse(bvh), bvh)).resource
    binary_nodes = TrackedTexels(context, "binary nodes", node_records(bvh)).resource
    shipped = hits(context, SHIPPED, triangles, wide_nodes, rays)
    binary = hits(context, binary_traversal_wgsl(), triangles, binary_nodes, rays)
    triangle, binary_triangle = shipped[:, 1].view(np.uint32), binary[:, 1].view(np.uint32)
    assert (binary_triangle != NO_TRIANGLE).mean() > 0.3, "too few rays hit anything to test"
    # bit for bit equal distances, the same triangle unless another was hit at that exact distance
    different_t = np.flatnonzero(shipped[:, 0] != binary[:, 0])
    assert different_t.size == 0, (
        f"{different_t.size} rays get another closest distance; first: ray {different_t[0]} shipped t "
        f"{shipped[different_t[0], 0]} triangle {triangle[different_t[0]]}, binary t {binary[different_t[0], 0]} "
        f"triangle {binary_triangle[different_t[0]]}"
    )
    ties = np.count_nonzero(triangle != binary_triangle)
    assert ties <= 0.01 * len(triangle), f"{ties} rays hit another triangle at the same distance: too many for ties"
    blocked = np.flatnonzero(shipped[:, 2] != binary[:, 2])
    assert blocked.size == 0, f"{blocked.size} rays occluded differently; first: ray {blocked[0]}"


@pytest.mark.parametrize("max_depth", [BUILD_MAX_DEPTH, SHALLOW_DEPTH])
def test_soup_hits_equal_binary(gpu_context, rng, max_depth):
    triangles = soup(rng)
    bvh = build_bvh(triangles, max_depth=max_depth, workers=1)
    reordered = triangle_records(triangles[bvh.triangle_order], np.zeros(len(triangles), np.uint32))
    origins = rng.uniform(-1.5, 1.5, size=(RAY_COUNT, 3)).astype(np.float32)
    rays = (origins, unit_vectors(rng, RAY_COUNT), rng.uniform(0.0, 2.0, RAY_COUNT))
    assert_shipped_finds_what_binary_finds(gpu_context, reordered, bvh, rays)


def test_cornell_camera_rays_hit_what_binary_hits(gpu_context, rng):
    scene = default_scene()
    origins, directions = pixel_centre_rays(scene.camera, CAMERA_RAYS_SIZE, CAMERA_RAYS_SIZE)
    rays = (origins, directions, rng.uniform(0.0, 4.0, len(origins)))
    records = scene_records(scene, "bvh")
    assert_shipped_finds_what_binary_finds(gpu_context, records.triangles, records.acceleration, rays)
