"""bench/kernel_variants/wide_nodes.py: the 4-wide records cover the tree, and the wide traversal
finds what the shipped one finds.

The shipped traversal is tested against float64 brute force (tests/shaders/test_traversal.py); the
wide one runs the same box and triangle arithmetic in another order, so it must return the very
same closest hits, except that of triangles hit at exactly the same distance it may pick another,
and the very same occlusion answers.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from bench.kernel_variants.wide_nodes import (
    WIDE_COUNT_BITS,
    WIDE_EMPTY,
    WIDE_LEAF,
    WIDE_LEAF_MAX,
    wide_records,
    wide_traversal_wgsl,
)
from bench.traversal_ceiling import pixel_centre_rays
from tests.harness import run_kernel
from tests.shaders.reference import as_vec4, unit_vectors
from wgputrace import default_scene
from wgputrace.bvh import build_bvh
from wgputrace.gpu.pipeline import NO_TRIANGLE
from wgputrace.gpu.texels import TrackedTexels
from wgputrace.render.scene_buffers import node_records, scene_records, triangle_records

SOUP_TRIANGLES = 2_000
RAY_COUNT = 3_000
# A builder stopped at this depth leaves leaves of ~SOUP_TRIANGLES / 2^(depth - 1) triangles, far
# over WIDE_LEAF_MAX: wide_records must split them.
SHALLOW_DEPTH = 4
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


def soup(rng: np.random.Generator) -> np.ndarray:
    centroids = rng.uniform(-1.0, 1.0, size=(SOUP_TRIANGLES, 1, 3))
    return (centroids + rng.normal(scale=0.1, size=(SOUP_TRIANGLES, 3, 3))).astype(np.float32)


def decode_leaves(records: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    words = records["children"].ravel()
    leaves = words[(words != WIDE_EMPTY) & ((words & WIDE_LEAF) != 0)]
    first = (leaves & ~np.uint32(WIDE_LEAF)) >> WIDE_COUNT_BITS
    return first.astype(np.int64), (leaves & (WIDE_LEAF_MAX - 1)).astype(np.int64) + 1


@pytest.mark.parametrize("max_depth", [64, SHALLOW_DEPTH])
def test_records_cover_every_triangle_and_record_once(rng, max_depth):
    bvh = build_bvh(soup(rng), max_depth=max_depth, workers=1)
    records = wide_records(bvh)
    first, count = decode_leaves(records)
    covered = np.zeros(SOUP_TRIANGLES, np.int64)
    np.add.at(covered, np.repeat(first, count) + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count), 1)
    wrong = np.flatnonzero(covered != 1)
    assert wrong.size == 0, f"{wrong.size} triangles in no leaf or several; first: {wrong[0]} in {covered[wrong[0]]}"
    words = records["children"]
    interior = words[(words != WIDE_EMPTY) & ((words & WIDE_LEAF) == 0)]
    assert np.array_equal(np.sort(interior), np.arange(1, len(records))), "records referenced other than once each"
    # the collapse adopts grandchildren until a record has four children or only leaves
    short = (words != WIDE_EMPTY).sum(axis=1) < 4
    with_interior = ((words != WIDE_EMPTY) & ((words & WIDE_LEAF) == 0)).any(axis=1)
    assert not (short & with_interior).any(), f"records {np.flatnonzero(short & with_interior)} could adopt more"


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


def assert_wide_finds_what_shipped_finds(context, records, rays: tuple[np.ndarray, ...], order: str) -> None:
    shipped_nodes = TrackedTexels(context, "nodes", records.nodes).resource
    wide_nodes = TrackedTexels(context, "wide nodes", wide_records(records.acceleration)).resource
    shipped = hits(context, SHIPPED, records.triangles, shipped_nodes, rays)
    wide = hits(context, wide_traversal_wgsl(order), records.triangles, wide_nodes, rays)
    triangle, shipped_triangle = wide[:, 1].view(np.uint32), shipped[:, 1].view(np.uint32)
    hit = shipped_triangle != NO_TRIANGLE
    assert hit.mean() > 0.3, "too few rays hit anything to test"
    # bit for bit equal distances, the same triangle unless another was hit at that exact distance
    different_t = np.flatnonzero(wide[:, 0] != shipped[:, 0])
    assert different_t.size == 0, (
        f"{different_t.size} rays get another closest distance; first: ray {different_t[0]} wide t "
        f"{wide[different_t[0], 0]} triangle {triangle[different_t[0]]}, shipped t {shipped[different_t[0], 0]} "
        f"triangle {shipped_triangle[different_t[0]]}"
    )
    ties = np.count_nonzero(triangle != shipped_triangle)
    assert ties <= 0.01 * len(triangle), f"{ties} rays hit another triangle at the same distance: too many for ties"
    blocked = np.flatnonzero(wide[:, 2] != shipped[:, 2])
    assert blocked.size == 0, f"{blocked.size} rays occluded differently; first: ray {blocked[0]}"


@pytest.mark.gpu
@pytest.mark.parametrize(("order", "max_depth"), [("sorted", 64), ("sorted", SHALLOW_DEPTH), ("nearest", 64)])
def test_soup_hits_equal_shipped(gpu_context, rng, order, max_depth):
    triangles = soup(rng)
    bvh = build_bvh(triangles, max_depth=max_depth, workers=1)
    reordered = triangle_records(triangles[bvh.triangle_order], np.zeros(SOUP_TRIANGLES, np.uint32))
    records = SimpleNamespace(triangles=reordered, nodes=node_records(bvh), acceleration=bvh)
    origins = rng.uniform(-1.5, 1.5, size=(RAY_COUNT, 3)).astype(np.float32)
    rays = (origins, unit_vectors(rng, RAY_COUNT), rng.uniform(0.0, 2.0, RAY_COUNT))
    assert_wide_finds_what_shipped_finds(gpu_context, records, rays, order)


@pytest.mark.gpu
def test_cornell_camera_rays_hit_what_shipped_hits(gpu_context, rng):
    scene = default_scene()
    origins, directions = pixel_centre_rays(scene.camera, CAMERA_RAYS_SIZE, CAMERA_RAYS_SIZE)
    rays = (origins, directions, rng.uniform(0.0, 4.0, len(origins)))
    assert_wide_finds_what_shipped_finds(gpu_context, scene_records(scene, "bvh"), rays, "sorted")
