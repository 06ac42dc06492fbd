"""Float64 numpy ray oracles for the shader, BVH and benchmark checks, and the packing both sides
of a comparison share.

Every oracle takes the float32 values the GPU sees (converted exactly to float64), so a difference
between the two is the shader's own rounding, never a difference in the inputs. Closest hits name
their triangle as the shaders do: NO_TRIANGLE on a miss, the smaller index on a tie.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from wgputrace.bvh import BVH
from wgputrace.gpu.layout import TRIANGLE
from wgputrace.kernels.structs import NO_TRIANGLE

# One float32 rounding (2^-24 relative); tolerances count how many of them can pile up.
UNIT_ROUNDOFF = 2.0**-24
# A crossing this close to an edge (in barycentric units) may fall on either side of it after the
# ~1e-7 relative rounding of the float32 edge functions; 100x that leaves room for cancellation.
EDGE_MARGIN = 1e-5
# The watertight test's t is a weighted mean of three sheared depths, weights from 2x2
# determinants of rounded sheared coordinates: a few tens of roundings of the coordinates'
# size, amplified by 1/|cos| because the determinant shrinks with the projected area at grazing
# incidence. (Measured on lavapipe: at most ~5 roundings / |cos|.)
T_ROUNDINGS = 32
# A triangle this far (relative) behind the closest hit cannot be taken for it by float32
# rounding unless |cos| < T_ROUNDINGS * UNIT_ROUNDOFF / AMBIGUOUS_T_SLACK ~ 2e-3.
AMBIGUOUS_T_SLACK = 1e-3

# Largest finite float32: what the shaders return as "no hit" (the WGSL FLOAT_MAX).
FLOAT_MAX = float(np.finfo(np.float32).max)

# Rays per chunk of the brute-force oracle: its (rays, triangles, 3) float64 temporaries stay
# at tens of MB for a few thousand triangles.
_CHUNK_RAYS = 128
# Rays traced together by the BVH oracle; bounds its (ray, node) pair arrays.
_BVH_RAY_BATCH = 4096


def as_vec4(xyz: np.ndarray) -> np.ndarray:
    """(n, 3) values as the (n, 4) float32 array a `array<vec4<f32>>` input reads (w = 0)."""
    out = np.zeros((len(xyz), 4), np.float32)
    out[:, :3] = xyz
    return out


def relative_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| / |b|, with |b| kept above the smallest normal float32."""
    return np.abs(a - b) / np.maximum(np.abs(b), np.finfo(np.float32).tiny)


def triangle_records(corners: np.ndarray) -> np.ndarray:
    """(n, 3, 3) corners as TRIANGLE records (material 0)."""
    records = TRIANGLE.zeros(len(corners))
    records["v0"], records["v1"], records["v2"] = corners[:, 0], corners[:, 1], corners[:, 2]
    return records


def record_corners(records: np.ndarray) -> np.ndarray:
    """TRIANGLE records back to (n, 3, 3) float32 corners."""
    return np.stack([records["v0"], records["v1"], records["v2"]], axis=1)


def normalized(v: np.ndarray) -> np.ndarray:
    """`v` divided by its length along the last axis."""
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def unit_vectors(rng: np.random.Generator, count: int) -> np.ndarray:
    """Directions uniform on the sphere, rounded to float32 (the rounded vectors are the rays)."""
    v = rng.normal(size=(count, 3))
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)


def triangle_normals(triangles: np.ndarray) -> np.ndarray:
    """Unit normals cross(v1 - v0, v2 - v0) of (n, 3, 3) triangles, in float64."""
    t = np.asarray(triangles, np.float64)
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


class Crossing(NamedTuple):
    """Where rays cross triangles' planes, from ray_triangle."""

    t: np.ndarray  # distance to the triangle where it is hit (t > 0, inside), else inf
    plane_t: np.ndarray  # signed distance to the plane, hit or not (0 where the ray is parallel to it)
    margin: np.ndarray  # smallest barycentric coordinate of the crossing: < 0 outside, ~0 near an edge
    cos: np.ndarray  # cosine between ray and normal; 0 in the plane or for a zero-area triangle


def ray_triangle(origins: np.ndarray, directions: np.ndarray, triangles: np.ndarray) -> Crossing:
    """Moller-Trumbore in float64, broadcasting rays (..., 3) against triangles (..., 3, 3).

    Rays in a triangle's plane and zero-area triangles (zero determinant) never hit.
    """
    o = np.asarray(origins, np.float64)
    d = np.asarray(directions, np.float64)
    v = np.asarray(triangles, np.float64)
    e1 = v[..., 1, :] - v[..., 0, :]
    e2 = v[..., 2, :] - v[..., 0, :]
    p = np.cross(d, e2)
    det = np.sum(e1 * p, axis=-1)
    normal_length = np.linalg.norm(np.cross(e1, e2), axis=-1)
    cos = np.divide(det, normal_length * np.linalg.norm(d, axis=-1), out=np.zeros_like(det), where=normal_length > 0)
    usable = det != 0.0
    inverse = np.where(usable, 1.0 / np.where(usable, det, 1.0), 0.0)
    s = o - v[..., 0, :]
    b1 = np.sum(s * p, axis=-1) * inverse
    q = np.cross(s, e1)
    b2 = np.sum(d * q, axis=-1) * inverse
    plane_t = np.sum(e2 * q, axis=-1) * inverse
    margin = np.where(usable, np.minimum(np.minimum(b1, b2), 1.0 - b1 - b2), -np.inf)
    hit = usable & (margin >= 0.0) & (plane_t > 0.0)
    return Crossing(np.where(hit, plane_t, np.inf), plane_t, margin, cos)


def ray_box(origins: np.ndarray, directions: np.ndarray, bounds_min: np.ndarray, bounds_max: np.ndarray) -> np.ndarray:
    """Entry distance (0 when starting inside) into closed boxes, inf on a miss, in float64.

    A zero direction component leaves its slab unbounded when the origin lies in the closed slab
    (faces included) and empty otherwise: a ray running along a face touches the box.
    """
    o = np.asarray(origins, np.float64)
    d = np.asarray(directions, np.float64)
    lo = np.asarray(bounds_min, np.float64)
    hi = np.asarray(bounds_max, np.float64)
    parallel = d == 0.0
    inside = (lo <= o) & (o <= hi)
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = (lo - o) / d
        t1 = (hi - o) / d
    near = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t0, t1))
    far = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t0, t1))
    enter = np.maximum(near.max(axis=-1), 0.0)
    leave = far.min(axis=-1)
    return np.where(enter <= leave, enter, np.inf)


def t_tolerance(t: np.ndarray, cos: np.ndarray, origins: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Absolute tolerance of float32 hit distances `t` of rays at `cos` to the triangle's normal.

    The sheared coordinates start with a subtraction (corner - origin), so their errors scale
    with the larger of the coordinates involved and the distance, not with t alone.
    """
    scale = np.maximum(np.abs(origins).max(axis=-1), np.abs(triangles).max(axis=(-2, -1)))
    return T_ROUNDINGS * UNIT_ROUNDOFF * np.maximum(t, scale) / np.abs(cos)


def brute_force_closest_hit(
    triangles: np.ndarray, origins: np.ndarray, directions: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest hit over all (n, 3, 3) triangles per ray: (t, triangle, ambiguous).

    t is inf and triangle NO_TRIANGLE on a miss. A ray is ambiguous when it passes within
    EDGE_MARGIN of an edge of a triangle that could be its closest hit (not more than
    AMBIGUOUS_T_SLACK behind the reference hit): float32 rounding may then decide either way.
    """
    count = len(origins)
    best_t = np.full(count, np.inf)
    best = np.full(count, NO_TRIANGLE, np.uint32)
    ambiguous = np.zeros(count, bool)
    for start in range(0, count, _CHUNK_RAYS):
        rows = slice(start, start + _CHUNK_RAYS)
        crossing = ray_triangle(origins[rows, None, :], directions[rows, None, :], triangles[None])
        t = crossing.t
        nearest = np.argmin(t, axis=1)
        chunk_t = t[np.arange(len(t)), nearest]
        best_t[rows] = chunk_t
        best[rows] = np.where(np.isfinite(chunk_t), nearest, NO_TRIANGLE)
        limit = np.where(np.isfinite(chunk_t), chunk_t * (1.0 + AMBIGUOUS_T_SLACK), np.inf)[:, None]
        plane_t = crossing.plane_t
        near_edge = (np.abs(crossing.margin) < EDGE_MARGIN) & (plane_t > 0.0) & (plane_t <= limit)
        ambiguous[rows] = near_edge.any(axis=1)
    return best_t, best, ambiguous


def bvh_closest_hit(
    bvh: BVH, vertices_reordered: np.ndarray, origins: np.ndarray, directions: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(t, triangle) per ray through `bvh`'s boxes, as the GPU traverses them; t is inf and
    triangle NO_TRIANGLE on a miss. `vertices_reordered` is the (N, 3, 3) triangle array already
    permuted by triangle_order; triangle points into it; equal distances resolve to the smaller
    index, as brute force does. The GPU's tests (box, descend or intersect, prune boxes entered
    beyond the closest hit) run on all rays at once, a tree level at a time, rather than a stack per
    ray (a per-ray Python loop costs milliseconds): the closest hit does not depend on the order.
    """
    triangles = np.asarray(vertices_reordered, dtype=np.float64)
    origins = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    directions = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    if triangles.shape != (len(bvh.triangle_order), 3, 3):
        raise ValueError(f"vertices_reordered must be ({len(bvh.triangle_order)}, 3, 3), got {triangles.shape}")
    if origins.shape != directions.shape:
        raise ValueError(f"origins {origins.shape} and directions {directions.shape} differ in shape")
    distance = np.full(len(origins), np.inf)
    triangle = np.full(len(origins), NO_TRIANGLE, np.uint32)
    for begin in range(0, len(origins), _BVH_RAY_BATCH):
        batch = slice(begin, begin + _BVH_RAY_BATCH)
        distance[batch], triangle[batch] = _bvh_closest_hit_batch(bvh, triangles, origins[batch], directions[batch])
    return distance, triangle


def _bvh_closest_hit_batch(
    bvh: BVH, triangles: np.ndarray, origins: np.ndarray, directions: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    ray_count = len(origins)
    best_t = np.full(ray_count, np.inf)
    no_hit = np.iinfo(np.int64).max  # larger than any index, so minimum.at replaces it
    best_index = np.full(ray_count, no_hit)
    # (ray, node) pairs still to test: a tree starts at its root, a flat list at every box.
    roots = np.zeros(1, np.int64) if bvh.kind == "bvh" else np.arange(bvh.node_count)
    ray = np.repeat(np.arange(ray_count), len(roots))
    node = np.tile(roots, ray_count)
    while ray.size:
        entry = ray_box(origins[ray], directions[ray], bvh.bounds_min[node], bvh.bounds_max[node])
        kept = np.isfinite(entry) & (entry <= best_t[ray])
        ray, node = ray[kept], node[kept]
        first = bvh.left_or_first[node].astype(np.int64)
        count = bvh.triangle_count[node].astype(np.int64)
        leaf = count > 0

        count = count[leaf]
        pair_ray = np.repeat(ray[leaf], count)
        pair_triangle = np.repeat(first[leaf] - (np.cumsum(count) - count), count) + np.arange(count.sum())
        t = ray_triangle(origins[pair_ray], directions[pair_ray], triangles[pair_triangle]).t
        previous_t = best_t.copy()
        np.minimum.at(best_t, pair_ray, t)
        best_index[best_t < previous_t] = no_hit
        attains = np.isfinite(t) & (t == best_t[pair_ray])
        np.minimum.at(best_index, pair_ray[attains], pair_triangle[attains])

        ray = np.repeat(ray[~leaf], 2)
        node = (first[~leaf, None] + np.arange(2)).ravel()
    return best_t, np.where(best_index == no_hit, NO_TRIANGLE, best_index).astype(np.uint32)


def bvh_bounds_from_scratch(bvh: BVH, vertices_reordered: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every node's bounds recomputed bottom-up (children have larger ids than their parent)."""
    low = np.empty_like(bvh.bounds_min)
    high = np.empty_like(bvh.bounds_max)
    for node in range(bvh.node_count - 1, -1, -1):
        first, count = int(bvh.left_or_first[node]), int(bvh.triangle_count[node])
        if count:
            corners = vertices_reordered[first : first + count].reshape(-1, 3)
            low[node], high[node] = corners.min(axis=0), corners.max(axis=0)
        else:
            low[node] = np.minimum(low[first], low[first + 1])
            high[node] = np.maximum(high[first], high[first + 1])
    return low, high


def fresnel_dielectric(cos_i: np.ndarray, eta_i: np.ndarray, eta_t: np.ndarray) -> np.ndarray:
    """Exact unpolarized Fresnel reflectance (mean of s and p), 1 under total internal reflection."""
    cos_i = np.abs(np.asarray(cos_i, np.float64))
    sin_t2 = (eta_i / eta_t) ** 2 * (1.0 - cos_i**2)
    cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin_t2))
    r_s = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t)
    r_p = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t)
    return np.where(sin_t2 >= 1.0, 1.0, 0.5 * (r_s**2 + r_p**2))
