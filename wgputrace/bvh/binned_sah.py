"""Binned surface-area-heuristic BVH builder, vectorized over all nodes of one tree level at a time.

Parameters of `build_bvh`:
    bin_count      16  centroid bins per axis and node; splits are tried between neighbouring bins
    max_leaf_size   4  a node with at most this many triangles becomes a leaf; a larger node is
                       always split, even where SAH would call a leaf cheaper, so the GPU's
                       per-leaf loop stays short (only max_depth can make a larger leaf)
    max_depth      64  levels at most; a node on the last level becomes a leaf whatever its size,
                       because the GPU traversal has a fixed 64-entry stack

Each level keeps the triangles of its nodes contiguous per node, nodes in order. Per-node bounds
are `reduceat` over those ranges, per-(bin, axis, node) counts and bounds are `bincount` and
`ufunc.at` over flat cell keys, scans over bins give every split's cost, and the chosen split
becomes a stable partition of each node's range computed from cumulative sums. Python loops run
over levels, axes, bins and cache-sized batches of nodes, never over single nodes or triangles.
"""

from __future__ import annotations

from time import perf_counter

import numpy as np

from wgputrace.bvh.tree import BVH, validated_vertices

AXES = 3
# Nodes are binned and partitioned in batches of about this many triangles so that temporaries
# stay in cache instead of being faulted in fresh from the OS at every level (measured 1.4x faster
# on 1e6 triangles; 2^15 to 2^17 perform alike). A batch is the nodes whose ranges start in one
# window of this size, so its last node may run past the window.
BATCH_TRIANGLES = 1 << 16


def build_bvh(vertices: np.ndarray, *, bin_count: int = 16, max_leaf_size: int = 4, max_depth: int = 64) -> BVH:
    """Build a BVH over (N, 3, 3) float32 triangles (triangle, corner, xyz)."""
    started = perf_counter()
    triangles = validated_vertices(vertices)
    for name, value, smallest in (
        ("bin_count", bin_count, 2),
        ("max_leaf_size", max_leaf_size, 1),
        ("max_depth", max_depth, 1),
    ):
        if value < smallest:
            raise ValueError(f"{name} must be at least {smallest}, got {value}")
    triangle_total = len(triangles)
    corner_min = np.minimum(np.minimum(triangles[:, 0], triangles[:, 1]), triangles[:, 2]).T
    corner_max = np.maximum(np.maximum(triangles[:, 0], triangles[:, 1]), triangles[:, 2]).T
    # Rows 0-2 box min, 3-5 box max, 6-8 box centroid (halves summed so huge coordinates cannot
    # overflow): one (9, n) array, so a partition moves everything with a single gather.
    boxes = np.concatenate([corner_min, corner_max, corner_min * 0.5 + corner_max * 0.5])
    ids = np.arange(triangle_total)

    node_capacity = 2 * triangle_total - 1  # a binary tree whose leaves are never empty
    bounds_min = np.empty((node_capacity, 3), np.float32)
    bounds_max = np.empty((node_capacity, 3), np.float32)
    left_or_first = np.empty(node_capacity, np.uint32)
    triangle_count = np.empty(node_capacity, np.uint32)
    triangle_order = np.empty(triangle_total, np.uint32)

    # The current level: node ids, start of each node's range in boxes/ids, its triangle count,
    # and its first slot in triangle_order.
    node = np.zeros(1, np.int64)
    start = np.zeros(1, np.int64)
    count = np.array([triangle_total], np.int64)
    first = np.zeros(1, np.int64)
    node_total = 1
    depth = 0
    while node.size:
        depth += 1
        bounds_min[node] = np.minimum.reduceat(boxes[0:3], start, axis=1).T
        bounds_max[node] = np.maximum.reduceat(boxes[3:6], start, axis=1).T
        is_leaf = (count <= max_leaf_size) | (depth == max_depth)
        if is_leaf.any():
            left_or_first[node[is_leaf]] = first[is_leaf]
            triangle_count[node[is_leaf]] = count[is_leaf]
            in_leaf = np.repeat(is_leaf, count)
            # A triangle's slot is its position shifted by its node's (first - start).
            triangle_order[np.flatnonzero(in_leaf) + np.repeat(first - start, count)[in_leaf]] = ids[in_leaf]
            boxes, ids = boxes[:, ~in_leaf], ids[~in_leaf]
            node, count, first = node[~is_leaf], count[~is_leaf], first[~is_leaf]
            start = np.cumsum(count) - count
        if not node.size:
            break

        # A split never moves a triangle out of its node's range, so every batch of nodes is
        # binned and partitioned within its own slice.
        left_count = np.empty_like(count)
        batch_edges = np.flatnonzero(np.diff(start // BATCH_TRIANGLES, prepend=-1, append=-1))
        for node_lo, node_hi in zip(batch_edges[:-1], batch_edges[1:], strict=True):
            batch = slice(start[node_lo], start[node_hi - 1] + count[node_hi - 1])
            is_left = _left_side(boxes[:, batch], count[node_lo:node_hi], bin_count)
            source, left_count[node_lo:node_hi] = _stable_partition(is_left, count[node_lo:node_hi])
            boxes[:, batch] = np.take(boxes[:, batch], source, axis=1)
            ids[batch] = ids[batch][source]

        left_or_first[node] = node_total + 2 * np.arange(node.size)
        triangle_count[node] = 0
        node = np.arange(node_total, node_total + 2 * node.size)
        node_total += node.size
        # Children interleave (left, right) per parent, matching their ids.
        start = np.column_stack([start, start + left_count]).ravel()
        first = np.column_stack([first, first + left_count]).ravel()
        count = np.column_stack([left_count, count - left_count]).ravel()

    return BVH(
        bounds_min=bounds_min[:node_total].copy(),
        bounds_max=bounds_max[:node_total].copy(),
        left_or_first=left_or_first[:node_total].copy(),
        triangle_count=triangle_count[:node_total].copy(),
        triangle_order=triangle_order,
        depth=depth,
        build_seconds=perf_counter() - started,
        kind="bvh",
    )


def _stable_partition(is_left: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gather order that splits each node's range into its left triangles, then its right ones,
    keeping their order; and the left count per node."""
    start = np.cumsum(count) - count
    left_count = np.add.reduceat(is_left, start, dtype=np.int64)
    left_before = np.cumsum(is_left) - is_left
    left_rank = left_before - np.repeat(left_before[start], count)
    node_start = np.repeat(start, count)
    right_rank = np.arange(is_left.size) - node_start - left_rank
    destination = node_start + np.where(is_left, left_rank, np.repeat(left_count, count) + right_rank)
    source = np.empty_like(destination)
    source[destination] = np.arange(destination.size)
    return source, left_count


def _left_side(boxes: np.ndarray, count: np.ndarray, bin_count: int) -> np.ndarray:
    """For every triangle of consecutive nodes, whether it goes left under its node's best binned SAH split.

    A node whose centroids allow no split with both sides non-empty (all centroids coincide) is
    cut in half by position instead, so its subtree stays logarithmic in depth.
    """
    node_count = count.size
    start = np.cumsum(count) - count
    corner_min, corner_max, centroid = boxes[0:3], boxes[3:6], boxes[6:9]
    centroid_min = np.minimum.reduceat(centroid, start, axis=1)
    extent = np.maximum.reduceat(centroid, start, axis=1) - centroid_min
    # The scale is formed in float64 and capped so a tiny extent cannot overflow it to inf; a zero
    # extent gets scale 0, putting every triangle in bin 0, which offers no split on that axis.
    with np.errstate(divide="ignore"):
        scale = np.where(extent > 0, bin_count / extent.astype(np.float64), 0.0)
    scale = np.minimum(scale, np.finfo(np.float32).max).astype(np.float32)
    relative = centroid - np.repeat(centroid_min, count, axis=1)
    relative *= np.repeat(scale, count, axis=1)
    bins = np.minimum(relative, bin_count - 1, out=relative).astype(np.intp)

    # Cells are (bin, axis, node), so scans over bins are whole-array operations. The node stride
    # is odd because node counts are often powers of two, and a power-of-two stride makes the
    # scattered updates below alias in the cache (measured twice as slow).
    stride = node_count | 1
    cells = (bin_count, AXES, stride)
    keys = bins * (AXES * stride)
    keys += np.arange(AXES)[:, None] * stride
    keys += np.repeat(np.arange(node_count), count)
    population = np.bincount(keys.ravel(), minlength=np.prod(cells)).reshape(cells)
    bin_min = np.full((3, *cells), np.inf, np.float32)
    bin_max = np.full((3, *cells), -np.inf, np.float32)
    for axis in range(AXES):
        for coordinate in range(3):
            np.minimum.at(bin_min[coordinate].reshape(-1), keys[axis], corner_min[coordinate])
            np.maximum.at(bin_max[coordinate].reshape(-1), keys[axis], corner_max[coordinate])

    # Split s puts bins [0, s] left and [s + 1, bin_count) right. The left scans run on copies,
    # the right scans in place on the bins themselves, which are not needed afterwards.
    left_population = _scan_bins(np.add, population)[:-1]
    right_population = np.pad(count, (0, stride - node_count)) - left_population
    left_area = _half_area(
        _scan_bins(np.minimum, bin_min.copy(), axis=1)[:, :-1],
        _scan_bins(np.maximum, bin_max.copy(), axis=1)[:, :-1],
    )
    right_area = _half_area(
        _scan_bins(np.minimum, bin_min[:, ::-1], axis=1)[:, -2::-1],
        _scan_bins(np.maximum, bin_max[:, ::-1], axis=1)[:, -2::-1],
    )
    with np.errstate(invalid="ignore"):  # an empty side has infinite area times zero triangles
        cost = left_area * left_population
        cost += right_area * right_population
    cost[(left_population == 0) | (right_population == 0)] = np.inf
    cost = cost.reshape(-1, stride)
    best = np.argmin(cost, axis=0)[:node_count]
    best_split, best_axis = np.divmod(best, AXES)
    has_split = np.isfinite(cost[best, np.arange(node_count)])

    chosen_bin = bins[np.repeat(best_axis, count), np.arange(bins.shape[1])]
    is_left = chosen_bin <= np.repeat(best_split, count)
    if not has_split.all():
        by_position = np.arange(bins.shape[1]) - np.repeat(start, count) < np.repeat(count // 2, count)
        is_left = np.where(np.repeat(has_split, count), is_left, by_position)
    return is_left


def _scan_bins(combine: np.ufunc, array: np.ndarray, axis: int = 0) -> np.ndarray:
    """Running `combine` over the bin axis, in place; returns `array`.

    A Python loop over bins: each step is one whole-array operation, several times faster than
    ufunc.accumulate, which walks the short bin axis element by element.
    """
    bins_first = np.moveaxis(array, axis, 0)
    for b in range(1, len(bins_first)):
        combine(bins_first[b - 1], bins_first[b], out=bins_first[b])
    return array


def _half_area(bounds_min: np.ndarray, bounds_max: np.ndarray) -> np.ndarray:
    """Half the surface area of boxes with xyz on the first axis, in float64: squares of float32
    extents can overflow or underflow float32, which would hide the differences between splits."""
    x, y, z = np.subtract(bounds_max, bounds_min, dtype=np.float64)
    area = x * y
    area += y * z
    area += z * x
    return area
