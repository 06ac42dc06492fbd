"""The canonical bounding volume hierarchy that every builder produces and every GPU layout reads.

Nodes are stored as four parallel arrays matching the 32-byte GPU node
(bounds_min, left_or_first, bounds_max, triangle_count); node 0 is the root.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

KINDS = ("bvh", "flat")


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
