"""Binned surface-area-heuristic BVH builder, vectorized over all nodes of one tree level at a time.

Python loops run over levels, axes, bins and cache-sized batches of nodes, never over single nodes
or triangles: a level keeps each node's triangles contiguous, one 40-byte record per triangle
(box, centroid, id), so a partition is one gather. Once a level's nodes fall into groups of about
equal size, each group's subtrees grow in a worker process of their own (`grow_groups`).
"""

from __future__ import annotations

from dataclasses import dataclass
from time import perf_counter

import numpy as np

from wgputrace.bvh.forked_subtrees import (
    FORK_MIN_TRIANGLES,
    available_workers,
    balanced_groups,
    grow_groups,
    shared_empty,
)
from wgputrace.bvh.levels import breadth_first_levels
from wgputrace.bvh.tree import BVH, validated_vertices

# Nodes are binned and partitioned in batches of about this many triangles so that temporaries
# stay in cache instead of being faulted in fresh from the OS at every level (measured 1.4x faster
# on 1e6 triangles; 2^15 to 2^17 perform alike). A batch is the nodes whose ranges start in one
# window of this size, so its last node may run past the window.
BATCH_TRIANGLES = 1 << 16
# Levels of a tree built without a max_depth of the caller's.
DEFAULT_MAX_DEPTH = 64
# One triangle while the tree is built: its box, the box's centre, and its input index.
RECORD = np.dtype([("min", np.float32, 3), ("max", np.float32, 3), ("centroid", np.float32, 3), ("id", np.uint32)])
# The same bytes as one opaque item: numpy gathers these with a plain copy (field by field for RECORD).
_RAW = np.dtype((np.void, RECORD.itemsize))
# The BVH fields kept per node.
NODE_FIELDS = ("bounds_min", "bounds_max", "left_or_first", "triangle_count")


def build_bvh(
    vertices: np.ndarray,
    *,
    bin_count: int = 16,
    max_leaf_size: int = 4,
    max_depth: int = DEFAULT_MAX_DEPTH,
    workers: int | None = None,
) -> BVH:
    """Build a BVH over (N, 3, 3) float32 triangles (triangle, corner, xyz).

    `bin_count`: centroid bins per axis and node. `max_leaf_size`: a larger node is always split, even
    where SAH would call a leaf cheaper, so the GPU's per-leaf loop stays short. `max_depth`: a node on
    that level becomes a leaf whatever its size (the renderer passes `BUILD_MAX_DEPTH`, which bounds
    its traversal stack). `workers`: processes growing subtrees (None: every CPU this process may
    use); the tree does not depend on it.
    """
    started = perf_counter()
    triangles = validated_vertices(vertices)
    workers = available_workers() if workers is None else workers
    for name, value, smallest in (
        ("bin_count", bin_count, 2),
        ("max_leaf_size", max_leaf_size, 1),
        ("max_depth", max_depth, 1),
        ("workers", workers, 1),
    ):
        if value < smallest:
            raise ValueError(f"{name} must be at least {smallest}, got {value}")
    triangle_total = len(triangles)
    # Boxes are formed contiguous and copied into the records once: arithmetic on the records'
    # 40-byte-strided fields runs several times slower.
    corner_min = np.minimum(np.minimum(triangles[:, 0], triangles[:, 1]), triangles[:, 2])
    corner_max = np.maximum(np.maximum(triangles[:, 0], triangles[:, 1]), triangles[:, 2])
    records = np.empty(triangle_total, RECORD)
    records["min"], records["max"] = corner_min, corner_max
    # halves summed, so huge coordinates cannot overflow
    records["centroid"] = corner_min * np.float32(0.5) + corner_max * np.float32(0.5)
    records["id"] = np.arange(triangle_total)

    forking = workers > 1 and triangle_total >= FORK_MIN_TRIANGLES
    # A binary tree whose leaves are never empty has at most 2N - 1 nodes; forked groups number
    # their nodes in ranges of their own, which take at most 2N more.
    tree = _NodeArrays(2 * triangle_total - 1 + (2 * triangle_total if forking else 0), triangle_total, forking)
    # per column: numpy reduces a long axis of a contiguous (N, 3) array an order slower
    tree.bounds_min[0] = [corner_min[:, axis].min() for axis in range(3)]
    tree.bounds_max[0] = [corner_max[:, axis].max() for axis in range(3)]
    grower = _LevelGrower(tree, bin_count, max_leaf_size, max_depth)
    # the root level, one node over every triangle
    level = _Level(
        np.zeros(1, np.int64), np.zeros(1, np.int64), np.array([triangle_total], np.int64), np.zeros(1, np.int64)
    )
    next_id, depth, edges = 1, 0, None
    while level.node.size and edges is None:
        records, level, next_id, depth = grower.grow(records, level, next_id, depth, levels=1)
        edges = balanced_groups(level.count, workers) if forking else None
    if edges is None:
        nodes = tree.first_nodes(next_id)  # numbered breadth first already
    else:
        # Group g takes ids from its own base on: 2 per triangle of the groups before it.
        triangles_before = np.concatenate([[0], np.cumsum(np.add.reduceat(level.count, edges[:-1]))])
        bases = next_id + 2 * triangles_before

        def grow_group(group: int) -> int:
            nodes = slice(edges[group], edges[group + 1])
            part = _Level(level.node[nodes], level.start[nodes], level.count[nodes], level.first[nodes])
            lo, hi = part.start[0], part.start[-1] + part.count[-1]
            part.start -= lo
            return grower.grow(records[lo:hi], part, int(bases[group]), depth)[3]

        depth = max(grow_groups(len(edges) - 1, grow_group))
        nodes = tree.renumbered(np.concatenate(breadth_first_levels(tree.left_or_first, tree.triangle_count)))

    return BVH(
        **nodes,
        triangle_order=np.array(tree.triangle_order),  # a copy: no shared memory outlives the build
        depth=depth,
        build_seconds=perf_counter() - started,
        kind="bvh",
    )


@dataclass
class _Level:
    """The nodes of one tree level, in order: their ids, the start of each one's range in the
    level's records, its triangle count, and its first slot in triangle_order. Their bounds are
    already set, by their parent's split."""

    node: np.ndarray
    start: np.ndarray
    count: np.ndarray
    first: np.ndarray


class _NodeArrays:
    """The tree as it is built: node fields by id and triangle_order, in shared memory where
    forked workers write them."""

    def __init__(self, node_capacity: int, triangle_total: int, shared: bool) -> None:
        empty = shared_empty if shared else np.empty
        self.bounds_min = empty((node_capacity, 3), np.float32)
        self.bounds_max = empty((node_capacity, 3), np.float32)
        self.left_or_first = empty((node_capacity,), np.uint32)
        self.triangle_count = empty((node_capacity,), np.uint32)
        self.triangle_order = empty((triangle_total,), np.uint32)

    def first_nodes(self, node_total: int) -> dict[str, np.ndarray]:
        """Copies of the node fields of ids [0, node_total)."""
        return {name: getattr(self, name)[:node_total].copy() for name in NODE_FIELDS}

    def renumbered(self, order: np.ndarray) -> dict[str, np.ndarray]:
        """The node fields of the nodes `order` lists, node order[k] becoming node k (children's
        ids follow)."""
        nodes = {name: getattr(self, name)[order] for name in NODE_FIELDS}
        new_id = np.empty(len(self.triangle_count), np.uint32)
        new_id[order] = np.arange(order.size)
        interior = nodes["triangle_count"] == 0
        nodes["left_or_first"][interior] = new_id[nodes["left_or_first"][interior]]
        return nodes


class _LevelGrower:
    """Grows the tree level by level under one set of build parameters."""

    def __init__(self, tree: _NodeArrays, bin_count: int, max_leaf_size: int, max_depth: int) -> None:
        self.tree, self.bin_count, self.max_leaf_size, self.max_depth = tree, bin_count, max_leaf_size, max_depth

    def grow(
        self, records: np.ndarray, level: _Level, next_id: int, depth: int, levels: int | None = None
    ) -> tuple[np.ndarray, _Level, int, int]:
        """Turn `level`'s small nodes into leaves and split the others, for `levels` levels (None:
        until none is left), numbering children from `next_id` on. `records` holds the level's
        triangles, each node's range contiguous. Returns the records, level, next free id and
        depth reached (levels from the root; a single leaf has depth 1)."""
        tree = self.tree
        grown = 0
        while level.node.size and grown != levels:
            grown += 1
            depth += 1
            node, start, count, first = level.node, level.start, level.count, level.first
            is_leaf = (count <= self.max_leaf_size) | (depth == self.max_depth)
            if is_leaf.any():
                tree.left_or_first[node[is_leaf]] = first[is_leaf]
                tree.triangle_count[node[is_leaf]] = count[is_leaf]
                in_leaf = np.repeat(is_leaf, count)
                # A triangle's slot is its position shifted by its node's (first - start).
                slots = np.flatnonzero(in_leaf) + np.repeat(first - start, count)[in_leaf]
                tree.triangle_order[slots] = records["id"][in_leaf]
                records = records.view(_RAW)[~in_leaf].view(RECORD)
                node, count, first = node[~is_leaf], count[~is_leaf], first[~is_leaf]
                start = np.cumsum(count) - count
            if not node.size:
                level = _Level(node, start, count, first)
                break

            # A split never moves a triangle out of its node's range, so every batch of nodes is
            # binned and partitioned within its own slice.
            left_count = np.empty_like(count)
            child_min = np.empty((node.size, 2, 3), np.float32)
            child_max = np.empty((node.size, 2, 3), np.float32)
            batch_edges = np.flatnonzero(np.diff(start // BATCH_TRIANGLES, prepend=-1, append=-1))
            for node_lo, node_hi in zip(batch_edges[:-1], batch_edges[1:], strict=True):
                nodes = slice(node_lo, node_hi)
                batch = records[start[node_lo] : start[node_hi - 1] + count[node_hi - 1]]
                is_left, child_min[nodes], child_max[nodes], exact = _split(batch, count[nodes], self.bin_count)
                source, left_count[nodes] = _stable_partition(is_left, count[nodes])
                raw = batch.view(_RAW)
                raw[...] = raw[source]
                if not exact:  # nodes cut by position
                    child_start = np.column_stack([start[nodes], start[nodes] + left_count[nodes]]).ravel()
                    child_start -= start[node_lo]
                    child_min[nodes] = np.minimum.reduceat(batch["min"], child_start).reshape(-1, 2, 3)
                    child_max[nodes] = np.maximum.reduceat(batch["max"], child_start).reshape(-1, 2, 3)

            tree.left_or_first[node] = next_id + 2 * np.arange(node.size)
            tree.triangle_count[node] = 0
            children = slice(next_id, next_id + 2 * node.size)
            next_id += 2 * node.size
            # Children interleave (left, right) per parent, matching their ids.
            tree.bounds_min[children] = child_min.reshape(-1, 3)
            tree.bounds_max[children] = child_max.reshape(-1, 3)
            level = _Level(
                np.arange(children.start, children.stop),
                np.column_stack([start, start + left_count]).ravel(),
                np.column_stack([left_count, count - left_count]).ravel(),
                np.column_stack([first, first + left_count]).ravel(),
            )
        return records, level, next_id, depth


def _stable_partition(is_left: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gather order that splits each node's range into its left triangles, then its right ones,
    keeping their order; and the left count per node."""
    start = np.cumsum(count) - count
    left_count = np.add.reduceat(is_left, start, dtype=np.int64)
    # With L the number of left triangles before each one, a left triangle's slot is
    # L + (start - L[start]) and a right one's i - L + (left_count + L[start]) (their ranks
    # within the node shifted to where each side begins).
    left_before = np.cumsum(is_left) - is_left
    at_start = left_before[start]
    destination = np.where(
        is_left,
        left_before + np.repeat(start - at_start, count),
        np.arange(is_left.size) - left_before + np.repeat(left_count + at_start, count),
    )
    source = np.empty_like(destination)
    source[destination] = np.arange(destination.size)
    return source, left_count


def _split(records: np.ndarray, count: np.ndarray, bin_count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """The best binned SAH split of consecutive nodes: for every triangle whether it goes left; the
    children's boxes (node, left/right, xyz); and whether those boxes are exact (False where a node
    could not be split by bins, so the boxes must be recomputed).

    A node whose centroids allow no split with both sides non-empty (all centroids coincide) is
    cut in half by position instead, so its subtree stays logarithmic in depth.
    """
    start = np.cumsum(count) - count
    best_split, best_axis, has_split, child_min, child_max, bins = _best_splits(
        records["min"].T, records["max"].T, records["centroid"].T, count, bin_count
    )
    is_left = bins[np.repeat(best_axis, count), np.arange(records.size)] <= np.repeat(best_split, count)
    if not has_split.all():
        by_position = np.arange(records.size) - np.repeat(start, count) < np.repeat(count // 2, count)
        is_left = np.where(np.repeat(has_split, count), is_left, by_position)
    return is_left, child_min, child_max, bool(has_split.all())


def _best_splits(
    corner_min: np.ndarray, corner_max: np.ndarray, centroid: np.ndarray, count: np.ndarray, bin_count: int
) -> tuple[np.ndarray, ...]:
    """Binned SAH over consecutive nodes of `count` triangles, with boxes (xyz, triangle) and the
    centroid coordinates to bin along (axes, triangle): per node the best split and its row in
    `centroid`, whether it has one with both sides non-empty, the children's boxes (node,
    left/right, xyz); and every triangle's bins (axes, triangle)."""
    axes, node_count = len(centroid), count.size
    start = np.cumsum(count) - count
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
    cells = (bin_count, axes, stride)
    keys = bins * (axes * stride)
    keys += np.arange(axes)[:, None] * stride
    keys += np.repeat(np.arange(node_count), count)
    population = np.bincount(keys.ravel(), minlength=np.prod(cells)).reshape(cells)
    bin_min = np.full((3, *cells), np.inf, np.float32)
    bin_max = np.full((3, *cells), -np.inf, np.float32)
    for axis in range(axes):
        for coordinate in range(3):
            np.minimum.at(bin_min[coordinate].reshape(-1), keys[axis], corner_min[coordinate])
            np.maximum.at(bin_max[coordinate].reshape(-1), keys[axis], corner_max[coordinate])

    # Split s puts bins [0, s] left and [s + 1, bin_count) right. The left scans run on copies,
    # the right scans in place on the bins themselves, which are not needed afterwards.
    left_population = _scan_bins(np.add, population)[:-1]
    right_population = np.pad(count, (0, stride - node_count)) - left_population
    left_min = _scan_bins(np.minimum, bin_min.copy(), axis=1)
    left_max = _scan_bins(np.maximum, bin_max.copy(), axis=1)
    # Over all bins of any axis the left scan holds the node's box: extents are divided by its
    # largest side, so float32 products neither overflow nor underflow whatever the scene's scale.
    node_size = np.max(left_max[:, -1, 0].astype(np.float64) - left_min[:, -1, 0], axis=0)
    left_min, left_max = left_min[:, :-1], left_max[:, :-1]
    right_min = _scan_bins(np.minimum, bin_min[:, ::-1], axis=1)[:, -2::-1]
    right_max = _scan_bins(np.maximum, bin_max[:, ::-1], axis=1)[:, -2::-1]
    with np.errstate(divide="ignore"):
        inverse_size = np.where(node_size > 0, 1.0 / node_size, 1.0)
    inverse_size = np.minimum(inverse_size, np.finfo(np.float32).max).astype(np.float32)
    with np.errstate(invalid="ignore"):  # an empty side has infinite area times zero triangles
        cost = _quarter_area(left_min, left_max, inverse_size) * left_population.astype(np.float32)
        cost += _quarter_area(right_min, right_max, inverse_size) * right_population.astype(np.float32)
    cost[(left_population == 0) | (right_population == 0)] = np.inf
    nodes = np.arange(node_count)
    best_split, best_axis = np.divmod(np.argmin(cost.reshape(-1, stride), axis=0)[:node_count], axes)
    has_split = np.isfinite(cost[best_split, best_axis, nodes])
    # (xyz, node, left/right) -> (node, left/right, xyz)
    child_min = np.stack([left_min[:, best_split, best_axis, nodes], right_min[:, best_split, best_axis, nodes]], -1)
    child_max = np.stack([left_max[:, best_split, best_axis, nodes], right_max[:, best_split, best_axis, nodes]], -1)
    return best_split, best_axis, has_split, child_min.transpose(1, 2, 0), child_max.transpose(1, 2, 0), bins


def _scan_bins(combine: np.ufunc, array: np.ndarray, axis: int = 0) -> np.ndarray:
    """Running `combine` over the bin axis, in place; returns `array`.

    A Python loop over bins: each step is one whole-array operation, several times faster than
    ufunc.accumulate, which walks the short bin axis element by element.
    """
    bins_first = np.moveaxis(array, axis, 0)
    for b in range(1, len(bins_first)):
        combine(bins_first[b - 1], bins_first[b], out=bins_first[b])
    return array


def _quarter_area(bounds_min: np.ndarray, bounds_max: np.ndarray, inverse_size: np.ndarray) -> np.ndarray:
    """A quarter of the surface area of boxes with xyz on the first axis and nodes on the last, their
    extents multiplied by the node's `inverse_size`. Half extents: the difference of two halved
    float32 coordinates cannot overflow (float32's largest finite value minus its negative would)."""
    x, y, z = (bounds_max * np.float32(0.5) - bounds_min * np.float32(0.5)) * inverse_size
    area = x * y
    area += y * z
    area += z * x
    return area
