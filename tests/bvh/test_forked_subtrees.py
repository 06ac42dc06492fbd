"""Subtrees grown in forked workers: the same tree as one process builds, and nothing lost when a
worker fails."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

from wgputrace.bvh import binned_sah, build_bvh
from wgputrace.bvh.forked_subtrees import FORK_MIN_TRIANGLES, balanced_groups, grow_groups, shared_empty
from wgputrace.bvh.levels import breadth_first_levels

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="workers are forked on Linux only")

NODE_FIELDS = ("bounds_min", "bounds_max", "left_or_first", "triangle_count", "triangle_order")


def clustered_soup(rng: np.random.Generator, count: int) -> np.ndarray:
    """Tiny triangles in a few dense clusters plus a handful of huge ones, so the root's splits are
    lopsided and groups form only a few levels down."""
    cluster = rng.integers(0, 5, count)
    centres = rng.uniform(-10.0, 10.0, (5, 3))[cluster] + rng.normal(scale=0.3, size=(count, 3))
    vertices = centres[:, None, :] + rng.normal(scale=0.01, size=(count, 3, 3))
    vertices[:8] = rng.uniform(-50.0, 50.0, (8, 3, 3))
    return vertices.astype(np.float32)


def identical_centroids(rng: np.random.Generator, count: int) -> np.ndarray:
    """Corners a, -a, 0: every centroid is the origin, so every node is cut by position."""
    corner = rng.normal(size=(count, 3)).astype(np.float32)
    return np.stack([corner, -corner, np.zeros_like(corner)], axis=1)


@pytest.mark.parametrize(
    ("make", "parameters"),
    [
        (clustered_soup, {}),
        (clustered_soup, {"max_leaf_size": 1}),  # 2N - 1 nodes: a group uses its whole id range
        (clustered_soup, {"max_depth": 7, "max_leaf_size": 2}),
        (identical_centroids, {}),
    ],
)
@pytest.mark.parametrize("workers", [2, 3])
def test_workers_build_the_tree_one_process_builds(rng, monkeypatch, make, parameters, workers):
    vertices = make(rng, FORK_MIN_TRIANGLES + 1000)
    alone = build_bvh(vertices, workers=1, **parameters)
    group_counts = []

    def counted(group_count, grow):
        group_counts.append(group_count)
        return grow_groups(group_count, grow)

    monkeypatch.setattr(binned_sah, "grow_groups", counted)
    shared = build_bvh(vertices, workers=workers, **parameters)
    assert group_counts == [workers]  # the subtrees did grow in workers
    for name in NODE_FIELDS:
        assert np.array_equal(getattr(shared, name), getattr(alone, name)), name
    assert shared.depth == alone.depth


def test_groups_are_grown_in_workers_and_a_failed_one_again_here():
    parent = os.getpid()
    grown_by = shared_empty((4,), np.int64)

    def grow(group: int) -> int:
        if group == 2 and os.getpid() != parent:
            raise RuntimeError("a worker failing halfway")
        grown_by[group] = os.getpid()
        return 10 + group

    assert grow_groups(4, grow) == [10, 11, 12, 13]
    assert grown_by[0] == parent and grown_by[2] == parent  # the failed group, grown again here
    assert grown_by[1] != parent and grown_by[3] != parent and grown_by[1] != grown_by[3]


def test_balanced_groups_cut_near_equal_shares_or_refuse():
    edges = balanced_groups(np.array([10, 10, 10, 10, 12, 8]), 2)
    assert edges.tolist() == [0, 3, 6]
    assert balanced_groups(np.array([10, 10, 10, 10, 12, 8]), 3).tolist() == [0, 2, 4, 6]
    assert balanced_groups(np.array([90, 5, 5]), 2) is None  # one node is most of the level
    assert balanced_groups(np.array([50]), 2) is None  # fewer nodes than workers


def test_single_process_numbering_is_breadth_first(rng):
    bvh = build_bvh(clustered_soup(rng, 5000), workers=1)
    order = np.concatenate(breadth_first_levels(bvh.left_or_first, bvh.triangle_count))
    assert np.array_equal(order, np.arange(bvh.node_count))


def test_rejects_zero_workers(rng):
    with pytest.raises(ValueError, match="workers must be at least 1"):
        build_bvh(clustered_soup(rng, 10), workers=0)
