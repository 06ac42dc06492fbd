"""The canonical binary tree collapsed into a 4-wide one, the layout the GPU traverses.

Only the GPU sees the wide tree; the builder, refit, the viewer's levels and the tests keep the
binary `BVH`. A wide node starts with its binary node's two children and adopts the children of
its largest-area interior child, twice. A child is one word (a record index, a leaf's WIDE_LEAF |
first << WIDE_COUNT_BITS | count - 1, or WIDE_EMPTY), so traversal keeps a one-word stack. Every
slot remembers its binary node (`WideBVH.slot_node`), so a refit regathers boxes instead of
collapsing again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .tree import BVH, box_surface_area

WIDTH = 4
# The renderer's builder depth limit. 32 levels of a binned-SAH tree hold far more than the
# 22.4 million triangles the triangle texels allow on lavapipe (the 328k-triangle sphere in the
# Cornell box is 22 deep).
BUILD_MAX_DEPTH = 32
WIDE_LEAF = 1 << 31
# build_bvh's leaves hold at most 4 triangles (its max_leaf_size); 8 leaves room for other settings,
# and 28 bits of first triangle exceed the 22.4 million the triangle texels hold on lavapipe.
WIDE_COUNT_BITS = 3
WIDE_LEAF_MAX = 1 << WIDE_COUNT_BITS
# the first triangle of a leaf has the bits between the count and WIDE_LEAF
WIDE_FIRST_LIMIT = 1 << (31 - WIDE_COUNT_BITS)
# Halving a leaf of fewer than WIDE_FIRST_LIMIT triangles until it holds at most WIDE_LEAF_MAX takes
# at most this many levels.
LEAF_SPLIT_LEVELS = (31 - WIDE_COUNT_BITS) - WIDE_COUNT_BITS
# Stack entries every tree the renderer builds fits in. A traversal pushes every child of a record
# but the nearest, so it holds at most WIDTH - 1 entries per wide level above it, and a tree whose
# leaves lie at most D binary levels deep has at most D wide levels. Splitting the leaves the
# builder made at BUILD_MAX_DEPTH adds at most LEAF_SPLIT_LEVELS. `collapse` counts each tree's
# exact need (`WideBVH.max_stack`), the stack the renderer compiles.
STACK_SIZE = (WIDTH - 1) * (BUILD_MAX_DEPTH + LEAF_SPLIT_LEVELS)
WIDE_EMPTY = 0xFFFFFFFF
EMPTY_SLOT = -1


@dataclass
class WideBVH:
    """A 4-wide tree over the binary tree's triangle order: per record and slot, the child word
    (`refs`) and the binary node whose box the slot holds (`slot_node`, EMPTY_SLOT where unused).
    Record 0 holds the root's children; each level's interior children are the next level's records.
    """

    refs: np.ndarray  # (records, WIDTH) uint32
    slot_node: np.ndarray  # (records, WIDTH) int64
    max_stack: int  # stack entries a traversal may hold, at most

    @property
    def record_count(self) -> int:
        return len(self.refs)

    def slot_bounds(self, bvh: BVH, records: np.ndarray | slice = slice(None)) -> tuple[np.ndarray, np.ndarray]:
        """(min, max) of the slots of `records`, (n, WIDTH, 3) each, from `bvh`'s current node
        boxes (zero for empty slots)."""
        node = self.slot_node[records]
        used = (node != EMPTY_SLOT)[..., None]
        node = np.maximum(node, 0)
        return np.where(used, bvh.bounds_min[node], 0.0), np.where(used, bvh.bounds_max[node], 0.0)


def collapse(bvh: BVH, stack_size: int = STACK_SIZE) -> WideBVH:
    """The 4-wide tree of `bvh`; ValueError if a traversal could need more than `stack_size` entries."""
    if bvh.kind != "bvh":
        raise ValueError(f"a wide tree needs a tree (kind 'bvh'), got kind {bvh.kind!r}")
    if len(bvh.triangle_order) > WIDE_FIRST_LIMIT:
        raise ValueError(
            f"{len(bvh.triangle_order):,} triangles: a wide leaf reference holds first triangles below "
            f"{WIDE_FIRST_LIMIT:,} only"
        )
    bounds_min, bounds_max, left_or_first, count, origin = _split_large_leaves(bvh)
    interior = count == 0
    area = box_surface_area(bounds_min, bounds_max)
    root = [left_or_first[0], left_or_first[0] + 1] if interior[0] else [0]
    children = np.full((1, WIDTH), EMPTY_SLOT, np.int64)
    children[0, : len(root)] = root
    # stack entries a traversal may hold on arriving at each record of the level
    arrival_stack = np.zeros(1, np.int64)
    deepest_stack = 0
    levels = []
    while len(children):
        for _ in range(WIDTH - 2):
            children = _adopt_largest(children, interior, area, left_or_first)
        levels.append(children)
        used = children != EMPTY_SLOT
        child_interior = used & interior[np.maximum(children, 0)]
        leaving_stack = arrival_stack + used.sum(axis=1) - 1
        deepest_stack = max(deepest_stack, int(leaving_stack.max()))
        arrival_stack = np.repeat(leaving_stack, child_interior.sum(axis=1))
        first = left_or_first[children[child_interior]].astype(np.int64)
        children = np.full((first.size, WIDTH), EMPTY_SLOT, np.int64)
        children[:, 0], children[:, 1] = first, first + 1
    if deepest_stack > stack_size:
        raise ValueError(
            f"a 4-wide traversal of this tree may hold {deepest_stack} stack entries, over the shader's "
            f"{stack_size}: its leaves lie {len(levels)} wide levels deep (a builder limited to "
            f"{BUILD_MAX_DEPTH} levels with leaves of at most {WIDE_LEAF_MAX} triangles always fits)"
        )

    # Level L + 1's records are level L's interior children in order, so counting interior
    # children over all records in order numbers the records they point to.
    children = np.concatenate(levels)
    used = children != EMPTY_SLOT
    node = np.maximum(children, 0)
    child_interior = used & interior[node]
    leaf = used & ~interior[node]
    refs = np.full(children.shape, WIDE_EMPTY, np.uint32)
    refs[child_interior] = 1 + np.arange(np.count_nonzero(child_interior))
    leaf_first, leaf_count = left_or_first[node[leaf]], count[node[leaf]]
    refs[leaf] = WIDE_LEAF | (leaf_first << WIDE_COUNT_BITS) | (leaf_count - 1)
    return WideBVH(refs, np.where(used, origin[node], EMPTY_SLOT), deepest_stack)


def _split_large_leaves(bvh: BVH) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The tree's (bounds_min, bounds_max, left_or_first, triangle_count) with every leaf of more
    than WIDE_LEAF_MAX triangles turned into an interior node over its two halves (new nodes
    appended, with the leaf's box: their triangles are not at hand here, and such leaves are rare),
    and each node's origin: the binary node whose box it has."""
    bounds_min, bounds_max = bvh.bounds_min, bvh.bounds_max
    left_or_first, count = bvh.left_or_first.copy(), bvh.triangle_count.copy()
    origin = np.arange(len(count), dtype=np.int64)
    large = np.flatnonzero(count > WIDE_LEAF_MAX)
    while large.size:
        first, total = left_or_first[large], count[large]
        half = total // 2
        left_or_first[large] = len(count) + 2 * np.arange(large.size)
        count[large] = 0
        # (left, right) pairs in the order of their parents
        parents = np.repeat(large, 2)
        bounds_min = np.concatenate([bounds_min, bounds_min[parents]])
        bounds_max = np.concatenate([bounds_max, bounds_max[parents]])
        origin = np.concatenate([origin, origin[parents]])
        left_or_first = np.concatenate([left_or_first, np.column_stack([first, first + half]).ravel()])
        count = np.concatenate([count, np.column_stack([half, total - half]).ravel()])
        large = np.flatnonzero(count > WIDE_LEAF_MAX)
    return bounds_min, bounds_max, left_or_first, count, origin


def _adopt_largest(
    children: np.ndarray, interior: np.ndarray, area: np.ndarray, left_or_first: np.ndarray
) -> np.ndarray:
    """Rows of node ids (EMPTY_SLOT: empty, slots filled from the left) with the largest-area
    interior node of each row replaced by its two children; rows without one unchanged."""
    used = children != EMPTY_SLOT
    node = np.maximum(children, 0)
    candidate = used & interior[node]
    rows = np.flatnonzero(candidate.any(axis=1))
    slot = np.argmax(np.where(candidate, area[node], -np.inf), axis=1)[rows]
    chosen = left_or_first[children[rows, slot]].astype(np.int64)
    adopted = children.copy()
    adopted[rows, slot] = chosen
    adopted[rows, used[rows].sum(axis=1)] = chosen + 1
    return adopted
