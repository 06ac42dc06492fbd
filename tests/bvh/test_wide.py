"""WideBVH (`collapse`): the 4-wide tree covers every triangle and record once, adopts until full, maps
each slot to the binary node whose box it holds, and fits the shader's stack."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.bvh import build_bvh
from wgputrace.bvh.wide import (
    BUILD_MAX_DEPTH,
    EMPTY_SLOT,
    STACK_SIZE,
    WIDE_COUNT_BITS,
    WIDE_EMPTY,
    WIDE_LEAF,
    WIDE_LEAF_MAX,
    WIDTH,
    collapse,
)
from wgputrace.testing.scenes import random_soup

SOUP_TRIANGLES = 2_000
# Corners scatter this far around their centre: large triangles whose boxes overlap.
SOUP_TRIANGLE_SIZE = 0.1
# A builder stopped at this depth leaves leaves of ~SOUP_TRIANGLES / 2^(depth - 1) triangles, far
# over WIDE_LEAF_MAX: collapse must split them.
SHALLOW_DEPTH = 4
# A needle of coincident-ish triangles that SAH cannot separate well: a deep, lopsided tree.
CHAIN_TRIANGLES = 3_000


def decode_leaves(refs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    words = refs.ravel()
    leaves = words[(words != WIDE_EMPTY) & ((words & WIDE_LEAF) != 0)]
    first = (leaves & ~np.uint32(WIDE_LEAF)) >> WIDE_COUNT_BITS
    return first.astype(np.int64), (leaves & (WIDE_LEAF_MAX - 1)).astype(np.int64) + 1


@pytest.mark.parametrize("max_depth", [BUILD_MAX_DEPTH, SHALLOW_DEPTH])
def test_records_cover_every_triangle_and_record_once(rng, max_depth):
    bvh = build_bvh(random_soup(rng, SOUP_TRIANGLES, SOUP_TRIANGLE_SIZE), max_depth=max_depth, workers=1)
    wide = collapse(bvh)
    first, count = decode_leaves(wide.refs)
    covered = np.zeros(SOUP_TRIANGLES, np.int64)
    np.add.at(covered, np.repeat(first, count) + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count), 1)
    wrong = np.flatnonzero(covered != 1)
    assert wrong.size == 0, f"{wrong.size} triangles in no leaf or several; first: {wrong[0]} in {covered[wrong[0]]}"
    words = wide.refs
    interior = words[(words != WIDE_EMPTY) & ((words & WIDE_LEAF) == 0)]
    assert np.array_equal(np.sort(interior), np.arange(1, wide.record_count)), "records referenced other than once each"
    # the collapse adopts grandchildren until a record has four children or only leaves
    short = (words != WIDE_EMPTY).sum(axis=1) < WIDTH
    with_interior = ((words != WIDE_EMPTY) & ((words & WIDE_LEAF) == 0)).any(axis=1)
    assert not (short & with_interior).any(), f"records {np.flatnonzero(short & with_interior)} could adopt more"


def test_each_slot_holds_the_box_of_its_binary_node(rng):
    bvh = build_bvh(random_soup(rng, SOUP_TRIANGLES, SOUP_TRIANGLE_SIZE), max_depth=BUILD_MAX_DEPTH, workers=1)
    wide = collapse(bvh)
    used = wide.refs != WIDE_EMPTY
    assert np.array_equal(wide.slot_node != EMPTY_SLOT, used)
    # no binary node in two slots, and every leaf in one (no leaves were split here); adopted
    # interior nodes are replaced by their children
    nodes = wide.slot_node[used]
    assert np.unique(nodes).size == nodes.size
    np.testing.assert_array_equal(np.sort(nodes[bvh.triangle_count[nodes] > 0]), np.flatnonzero(bvh.triangle_count > 0))
    # a leaf slot's triangle range is its binary leaf's, so the map points at the right node
    leaf = used & ((wide.refs & WIDE_LEAF) != 0)
    first = (wide.refs[leaf] & ~np.uint32(WIDE_LEAF)) >> WIDE_COUNT_BITS
    np.testing.assert_array_equal(first, bvh.left_or_first[wide.slot_node[leaf]])
    bounds_min, bounds_max = wide.slot_bounds(bvh)
    np.testing.assert_array_equal(bounds_min[used], bvh.bounds_min[wide.slot_node[used]])
    np.testing.assert_array_equal(bounds_max[~used], 0.0)


def test_split_leaves_keep_the_box_of_the_leaf_they_came_from(rng):
    bvh = build_bvh(random_soup(rng, SOUP_TRIANGLES, SOUP_TRIANGLE_SIZE), max_depth=SHALLOW_DEPTH, workers=1)
    wide = collapse(bvh)
    used = wide.refs != WIDE_EMPTY
    leaf = used & ((wide.refs & WIDE_LEAF) != 0)
    source = wide.slot_node[leaf]
    first = ((wide.refs[leaf] & ~np.uint32(WIDE_LEAF)) >> WIDE_COUNT_BITS).astype(np.int64)
    # every piece lies inside the triangle range of the binary leaf whose box it holds
    start = bvh.left_or_first[source].astype(np.int64)
    assert (bvh.triangle_count[source] > 0).all()
    assert ((start <= first) & (first < start + bvh.triangle_count[source])).all()


def test_trees_of_the_renderers_depth_fit_the_stack(rng):
    """A lopsided tree (a long thin fan: every split peels off a few triangles) as deep as the
    renderer's builder goes: its worst-case stack stays within STACK_SIZE."""
    angles = np.sort(rng.uniform(0.0, 1.0, CHAIN_TRIANGLES)) ** 8
    tips = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1)
    triangles = np.stack([np.zeros_like(tips), tips, tips + [0.0, 0.0, 1e-3]], axis=1).astype(np.float32)
    bvh = build_bvh(triangles, max_depth=BUILD_MAX_DEPTH, workers=1)
    assert bvh.depth > BUILD_MAX_DEPTH // 2
    wide = collapse(bvh)
    assert 0 < wide.max_stack <= STACK_SIZE


def test_a_tree_over_the_stack_is_refused_with_the_count(rng):
    bvh = build_bvh(random_soup(rng, SOUP_TRIANGLES, SOUP_TRIANGLE_SIZE), max_depth=BUILD_MAX_DEPTH, workers=1)
    need = collapse(bvh).max_stack
    with pytest.raises(ValueError, match=f"may hold {need} stack entries, over the shader's {need - 1}"):
        collapse(bvh, stack_size=need - 1)
