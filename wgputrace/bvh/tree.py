"""The canonical bounding volume hierarchy that every builder produces and every GPU layout reads.

Nodes are stored as four parallel arrays matching the 32-byte GPU node
(bounds_min, left_or_first, bounds_max, triangle_count); node 0 is the root.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

KINDS = ("bvh", "flat")

# Moller-Trumbore divides by the determinant; below this fraction of |e1| |e2| |d| the ray is
# treated as parallel to the triangle's plane. Zero-area triangles always land here, so they are
# never hit, and float64 rounding of a parallel ray cannot produce a huge bogus distance.
PARALLEL_TOLERANCE = 1e-12
# Rays traced together by the reference traversal; bounds its (ray, node) pair arrays.
RAY_BATCH = 4096


def validated_vertices(vertices: np.ndarray) -> np.ndarray:
    """Return triangle corners as a contiguous (N, 3, 3) float32 array, or raise ValueError naming the problem."""
    triangles = np.ascontiguousarray(vertices, dtype=np.float32)
    if triangles.ndim != 3 or triangles.shape[1:] != (3, 3):
        raise ValueError(f"vertices must have shape (N, 3, 3) (triangle, corner, xyz), got {triangles.shape}")
    if len(triangles) == 0:
        raise ValueError("vertices holds no triangles; a BVH needs at least one")
    finite = np.isfinite(triangles).all(axis=(1, 2))
    if not finite.all():
        bad = np.flatnonzero(~finite)
        raise ValueError(
            f"triangle {bad[0]} has a non-finite vertex coordinate (NaN or inf after conversion to float32); "
            f"{bad.size} triangle(s) affected"
        )
    return triangles


def box_surface_area(bounds_min: np.ndarray, bounds_max: np.ndarray) -> np.ndarray:
    """Surface area of axis-aligned boxes with xyz on the last axis, in float64 so large scenes cannot overflow."""
    extent = np.subtract(bounds_max, bounds_min, dtype=np.float64)
    x, y, z = extent[..., 0], extent[..., 1], extent[..., 2]
    return 2.0 * (x * y + y * z + z * x)


def ray_triangle_distance(triangles: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Float64 Moller-Trumbore distance along the ray, inf for a miss; both faces count, only t > 0 is a hit.

    `triangles` is (..., 3, 3); `origin` and `direction` are (..., 3) and broadcast against it.
    """
    corners = np.asarray(triangles, dtype=np.float64)
    origin = np.asarray(origin, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    edge1 = corners[..., 1, :] - corners[..., 0, :]
    edge2 = corners[..., 2, :] - corners[..., 0, :]
    p = np.cross(direction, edge2)
    determinant = np.sum(edge1 * p, axis=-1)
    scale = np.linalg.norm(edge1, axis=-1) * np.linalg.norm(edge2, axis=-1) * np.linalg.norm(direction, axis=-1)
    usable = np.abs(determinant) > PARALLEL_TOLERANCE * scale
    inverse = 1.0 / np.where(usable, determinant, 1.0)
    s = origin - corners[..., 0, :]
    u = np.sum(s * p, axis=-1) * inverse
    q = np.cross(s, edge1)
    v = np.sum(direction * q, axis=-1) * inverse
    t = np.sum(edge2 * q, axis=-1) * inverse
    hit = usable & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    return np.where(hit, t, np.inf)


def _slab_entry(bounds_min: np.ndarray, bounds_max: np.ndarray, origin: np.ndarray, inverse: np.ndarray) -> np.ndarray:
    """Distance at which each ray enters its box (0 if it starts inside), inf where it misses; (P, 3) inputs."""
    with np.errstate(invalid="ignore"):
        t0 = (bounds_min - origin) * inverse
        t1 = (bounds_max - origin) * inverse
    # The f-variants skip the NaN of 0 * inf, a ray parallel to a slab starting on its plane, so
    # that slab does not constrain the ray.
    near = np.fmax(np.fmax.reduce(np.fmin(t0, t1), axis=1), 0.0)
    far = np.fmin.reduce(np.fmax(t0, t1), axis=1)
    return np.where(near <= far, near, np.inf)


@dataclass(frozen=True, eq=False)  # eq=False: comparing array fields with == is ambiguous
class BVH:
    """A bounding volume hierarchy (or trac0r's flat box list) over triangles reordered by triangle_order."""

    bounds_min: np.ndarray  # (M, 3) float32
    bounds_max: np.ndarray  # (M, 3) float32
    left_or_first: np.ndarray  # (M,) uint32: interior -> left child (right = left + 1); leaf -> first triangle
    triangle_count: np.ndarray  # (M,) uint32: 0 for interior nodes, >= 1 for leaves
    triangle_order: np.ndarray  # (N,) uint32: reordered position k holds input triangle triangle_order[k]
    depth: int  # number of levels; a single leaf has depth 1
    build_seconds: float
    kind: str  # "bvh": tree rooted at node 0; "flat": every node is a leaf tested by every ray

    def __post_init__(self) -> None:
        m = len(self.triangle_count)
        expected = {
            "bounds_min": (np.float32, (m, 3)),
            "bounds_max": (np.float32, (m, 3)),
            "left_or_first": (np.uint32, (m,)),
            "triangle_count": (np.uint32, (m,)),
            "triangle_order": (np.uint32, self.triangle_order.shape[:1]),
        }
        for name, (dtype, shape) in expected.items():
            array = getattr(self, name)
            if array.dtype != dtype or array.shape != shape:
                raise ValueError(f"BVH.{name} must be {np.dtype(dtype).name} {shape}, got {array.dtype} {array.shape}")
        if self.kind not in KINDS:
            raise ValueError(f"BVH.kind must be one of {KINDS}, got {self.kind!r}")

    @property
    def node_count(self) -> int:
        return len(self.triangle_count)

    def sah_cost(self, traversal_cost: float = 1.0, intersection_cost: float = 1.0) -> float:
        """Expected cost of one ray under the surface area heuristic.

        kind "bvh": the standard sum  C_t * A(n)/A(root)  over interior nodes plus
        C_i * count * A(n)/A(root)  over leaves.
        kind "flat": every ray tests every box, so  C_t * M, plus each box's triangles with the
        probability that a ray hitting the scene hits that box:  C_i * count * A(n)/A(scene),
        where the scene box is the union of all node boxes.
        A scene whose box has zero area (all geometry in one point) gives every node probability 1.
        """
        areas = box_surface_area(self.bounds_min, self.bounds_max)
        if self.kind == "bvh":
            scene_area = areas[0]
        else:
            scene_area = float(box_surface_area(self.bounds_min.min(axis=0), self.bounds_max.max(axis=0)))
        probability = areas / scene_area if scene_area > 0.0 else np.ones_like(areas)
        counts = self.triangle_count.astype(np.float64)
        leaf_cost = intersection_cost * float(np.sum(probability * counts))
        if self.kind == "flat":
            return traversal_cost * self.node_count + leaf_cost
        return traversal_cost * float(np.sum(probability[counts == 0])) + leaf_cost

    def closest_hit(
        self, vertices_reordered: np.ndarray, origins: np.ndarray, directions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Reference traversal: (t, index) per ray; t is inf and index -1 on a miss.

        `vertices_reordered` is the (N, 3, 3) triangle array already permuted by triangle_order;
        index points into it. Equal distances resolve to the smaller index, as an argmin over all
        triangles would, so the result can be compared with brute force exactly.

        The GPU's tests (box, descend into both children or intersect the leaf, prune boxes
        entered beyond the closest hit so far) are applied to all rays at once, one tree level at
        a time, instead of with a stack per ray: per-ray Python loops cost milliseconds a ray.
        The closest hit does not depend on the visiting order, so the answer is the same.
        """
        triangles = np.asarray(vertices_reordered, dtype=np.float64)
        origins = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
        directions = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
        if triangles.shape != (len(self.triangle_order), 3, 3):
            raise ValueError(f"vertices_reordered must be ({len(self.triangle_order)}, 3, 3), got {triangles.shape}")
        if origins.shape != directions.shape:
            raise ValueError(f"origins {origins.shape} and directions {directions.shape} differ in shape")
        distance = np.full(len(origins), np.inf)
        index = np.full(len(origins), -1, np.int64)
        for begin in range(0, len(origins), RAY_BATCH):
            batch = slice(begin, begin + RAY_BATCH)
            distance[batch], index[batch] = self._closest_hit_batch(triangles, origins[batch], directions[batch])
        return distance, index

    def _closest_hit_batch(
        self, triangles: np.ndarray, origins: np.ndarray, directions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        ray_count = len(origins)
        with np.errstate(divide="ignore"):
            inverse = 1.0 / directions
        best_t = np.full(ray_count, np.inf)
        no_hit = np.iinfo(np.int64).max  # larger than any index, so minimum.at replaces it
        best_index = np.full(ray_count, no_hit)
        # (ray, node) pairs still to test: a tree starts at its root, a flat list at every box.
        roots = np.zeros(1, np.int64) if self.kind == "bvh" else np.arange(self.node_count)
        ray = np.repeat(np.arange(ray_count), len(roots))
        node = np.tile(roots, ray_count)
        while ray.size:
            entry = _slab_entry(self.bounds_min[node], self.bounds_max[node], origins[ray], inverse[ray])
            kept = np.isfinite(entry) & (entry <= best_t[ray])
            ray, node = ray[kept], node[kept]
            first = self.left_or_first[node].astype(np.int64)
            count = self.triangle_count[node].astype(np.int64)
            leaf = count > 0

            count = count[leaf]
            pair_ray = np.repeat(ray[leaf], count)
            pair_triangle = np.repeat(first[leaf] - (np.cumsum(count) - count), count) + np.arange(count.sum())
            t = ray_triangle_distance(triangles[pair_triangle], origins[pair_ray], directions[pair_ray])
            previous_t = best_t.copy()
            np.minimum.at(best_t, pair_ray, t)
            best_index[best_t < previous_t] = no_hit
            attains = np.isfinite(t) & (t == best_t[pair_ray])
            np.minimum.at(best_index, pair_ray[attains], pair_triangle[attains])

            ray = np.repeat(ray[~leaf], 2)
            node = (first[~leaf, None] + np.arange(2)).ravel()
        best_index[best_index == no_hit] = -1
        return best_t, best_index
