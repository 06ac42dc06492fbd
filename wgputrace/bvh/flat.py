"""trac0r's acceleration structure: a flat list with one bounding box per shape, in the canonical node format.

Every node is a leaf; the GPU tests every box and then the triangles of each box that is hit.
"""

from __future__ import annotations

from time import perf_counter

import numpy as np

from wgputrace.bvh.tree import BVH, validated_vertices


def build_flat(vertices: np.ndarray, group_index: np.ndarray) -> BVH:
    """One leaf per shape id in `group_index` (N,), in increasing id order; triangles keep their order within a shape."""
    started = perf_counter()
    triangles = validated_vertices(vertices)
    groups = np.asarray(group_index)
    if groups.shape != (len(triangles),):
        raise ValueError(
            f"group_index must have shape ({len(triangles)},), one shape id per triangle, got {groups.shape}"
        )
    if not np.issubdtype(groups.dtype, np.integer):
        raise ValueError(f"group_index must hold integers, got dtype {groups.dtype}")
    order = np.argsort(groups, kind="stable")
    sorted_groups = groups[order]
    first = np.flatnonzero(np.concatenate([[True], sorted_groups[1:] != sorted_groups[:-1]]))
    count = np.diff(np.append(first, len(triangles)))
    reordered = triangles[order]
    return BVH(
        bounds_min=np.minimum.reduceat(reordered.min(axis=1), first, axis=0),
        bounds_max=np.maximum.reduceat(reordered.max(axis=1), first, axis=0),
        left_or_first=first.astype(np.uint32),
        triangle_count=count.astype(np.uint32),
        triangle_order=order.astype(np.uint32),
        depth=1,
        build_seconds=perf_counter() - started,
        kind="flat",
    )
