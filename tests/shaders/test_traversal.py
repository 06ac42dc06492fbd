"""closest_hit of both traversals (the BVH's over the binned-SAH tree, the flat list's over per-shape
boxes) against float64 brute force over every triangle."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Scene, Shape, default_scene
from wgputrace.gpu.layout import TRIANGLE
from wgputrace.gpu.texels import texels_per_record, texture_shape
from wgputrace.kernels.structs import NO_TRIANGLE
from wgputrace.render.scene_mirror import scene_records
from wgputrace.render.scene_records import ACCELERATIONS, SceneRecords
from wgputrace.testing.oracles import (
    brute_force_closest_hit,
    ray_triangle,
    record_corners,
    t_tolerance,
    triangle_normals,
    unit_vectors,
)
from wgputrace.testing.traversal import closest_hit

pytestmark = pytest.mark.gpu

RAY_COUNT = 3_000
SOUP_TRIANGLES = 2_000
# Shapes the soup is split into: the flat traversal gets one box per shape.
SOUP_SHAPES = 8
# Reachability grid: one small triangle per cell of a GRID^3 lattice of unit spacing.
GRID = 12
# Corners lie this far from their centroid, jitter moves the centroid, and rays start this far
# out along the normal: 0.15 + 0.1 + 0.2 < 0.5 keeps every ray inside its own cell, unoccluded.
GRID_TRIANGLE_RADIUS = 0.15
GRID_JITTER = 0.1
GRID_RAY_START = 0.2


def assert_matches_brute_force(context, records: SceneRecords, origins: np.ndarray, directions: np.ndarray) -> None:
    """Same triangle (or, on a tie, one the reference hits at the same distance), same t, same misses."""
    triangles = record_corners(records.triangles)
    t, triangle = closest_hit(context, records, origins, directions)
    reference_t, reference, ambiguous = brute_force_closest_hit(triangles, origins, directions)
    assert ambiguous.mean() < 0.01, f"{ambiguous.sum()} of {len(origins)} rays pass an edge: too few left to test"
    decided = np.flatnonzero(~ambiguous)
    miss = reference[decided] == NO_TRIANGLE
    wrong_miss = decided[miss & (triangle[decided] != NO_TRIANGLE)]
    assert wrong_miss.size == 0, (
        f"{wrong_miss.size} rays that miss everything hit a triangle; first: ray {wrong_miss[0]} "
        f"hit {triangle[wrong_miss[0]]} at t {t[wrong_miss[0]]}"
    )
    rays = decided[~miss]
    lost = rays[triangle[rays] == NO_TRIANGLE]
    assert lost.size == 0, (
        f"{lost.size} of {rays.size} rays miss although brute force hits; first: ray {lost[0]} origin "
        f"{origins[lost[0]].tolist()} direction {directions[lost[0]].tolist()} should hit {reference[lost[0]]} "
        f"at t {reference_t[lost[0]]}"
    )
    # The reference's view of the triangle the GPU chose: a different index is a tie only if the
    # reference hits that one at the same distance too (coplanar or touching triangles).
    chosen = ray_triangle(origins[rays], directions[rays], triangles[triangle[rays]])
    cos = ray_triangle(origins[rays], directions[rays], triangles[reference[rays]]).cos
    tolerance = t_tolerance(reference_t[rays], cos, origins[rays], triangles[reference[rays]])
    other = (triangle[rays] != reference[rays]) & ~(np.abs(chosen.t - reference_t[rays]) <= tolerance)
    bad = rays[other]
    assert bad.size == 0, (
        f"{bad.size} of {rays.size} rays hit another triangle than brute force; first: ray {bad[0]} hit "
        f"{triangle[bad[0]]} at t {t[bad[0]]}, brute force {reference[bad[0]]} at t {reference_t[bad[0]]}"
    )
    error = np.abs(t[rays] - reference_t[rays])
    worst = np.argmax(error / tolerance)
    assert error[worst] <= tolerance[worst], (
        f"ray {rays[worst]}: t {t[rays[worst]]} vs brute force {reference_t[rays[worst]]} "
        f"(allowed {tolerance[worst]:.3g} at cos {cos[worst]:.3g})"
    )


def soup_records(triangles: np.ndarray, shape_of: np.ndarray, acceleration: str) -> SceneRecords:
    material = Diffuse("white")
    shapes = [Shape(f"part {s}", triangles[shape_of == s], material) for s in np.unique(shape_of)]
    return scene_records(Scene(shapes), acceleration)


@pytest.mark.parametrize("acceleration", ACCELERATIONS)
def test_random_soup_matches_brute_force(gpu_context, rng, acceleration):
    centroids = rng.uniform(-1.0, 1.0, size=(SOUP_TRIANGLES, 1, 3))
    triangles = (centroids + rng.normal(scale=0.1, size=(SOUP_TRIANGLES, 3, 3))).astype(np.float32)
    # Shapes are spatial slabs along x, so the flat list's boxes overlap only partly.
    shape_of = np.minimum(((centroids[:, 0, 0] + 1.0) * SOUP_SHAPES / 2.0).astype(int), SOUP_SHAPES - 1)
    records = soup_records(triangles, shape_of, acceleration)
    origins = rng.uniform(-1.5, 1.5, size=(RAY_COUNT, 3)).astype(np.float32)
    assert_matches_brute_force(gpu_context, records, origins, unit_vectors(rng, RAY_COUNT))


@pytest.mark.parametrize("acceleration", ACCELERATIONS)
def test_cornell_box_from_inside_matches_brute_force(gpu_context, rng, acceleration):
    records = scene_records(default_scene(), acceleration)
    points = record_corners(records.triangles).reshape(-1, 3)
    low, high = points.min(axis=0), points.max(axis=0)
    # Inside the walls (the box is open at the front, towards the camera, so some rays escape).
    inset = 0.01 * (high - low)
    origins = rng.uniform(low + inset, high - inset, size=(RAY_COUNT, 3)).astype(np.float32)
    directions = unit_vectors(rng, RAY_COUNT)
    assert_matches_brute_force(gpu_context, records, origins, directions)


@pytest.mark.parametrize("acceleration", ACCELERATIONS)
def test_every_triangle_is_reachable(gpu_context, rng, acceleration):
    cells = np.stack(np.meshgrid(*[np.arange(GRID)] * 3, indexing="ij"), axis=-1).reshape(-1, 3).astype(np.float64)
    centroids = cells + rng.uniform(-GRID_JITTER, GRID_JITTER, size=cells.shape)
    # Corners on a circle of radius GRID_TRIANGLE_RADIUS in a random plane, 120 degrees apart.
    normals = unit_vectors(rng, len(cells)).astype(np.float64)
    tangent = np.cross(normals, unit_vectors(rng, len(cells)))
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    bitangent = np.cross(normals, tangent)
    angles = rng.uniform(0.0, 2.0 * np.pi, size=(len(cells), 1)) + np.array([0.0, 2.0, 4.0]) * np.pi / 3.0
    offsets = np.cos(angles)[..., None] * tangent[:, None] + np.sin(angles)[..., None] * bitangent[:, None]
    triangles = (centroids[:, None] + GRID_TRIANGLE_RADIUS * offsets).astype(np.float32)
    shape_of = (cells[:, 0] * SOUP_SHAPES // GRID).astype(int)
    records = soup_records(triangles, shape_of, acceleration)

    # The triangles' texture (`texture_shape`) has many rows, and with 3 texels a triangle some straddle
    # two: a triangle read from the wrong texel would not be the one its ray is aimed at.
    width, height = texture_shape(len(records.triangles) * texels_per_record(TRIANGLE))
    assert height > 1 and width % texels_per_record(TRIANGLE)
    placed = record_corners(records.triangles).astype(np.float64)
    normal = triangle_normals(placed)
    centroid = placed.mean(axis=1)
    origins = (centroid + GRID_RAY_START * normal).astype(np.float32)
    t, triangle = closest_hit(gpu_context, records, origins, (-normal).astype(np.float32))
    expected = np.arange(len(placed), dtype=np.uint32)
    unreached = np.flatnonzero(triangle != expected)
    assert unreached.size == 0, (
        f"{unreached.size} of {len(placed)} triangles not returned for a ray aimed at their centroid; first: "
        f"triangle {unreached[0]} got {triangle[unreached[0]]} at t {t[unreached[0]]}"
    )
