"""Tree levels and box edges, as the viewer's BVH overlay draws them."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import default_scene
from wgputrace.bvh.levels import box_edges, node_levels
from wgputrace.render.scene_mirror import scene_records
from wgputrace.render.scene_records import node_records


def test_levels_of_the_default_scene_tree_match_a_recursive_walk():
    nodes = node_records(scene_records(default_scene()).acceleration)
    levels = node_levels(nodes["left_or_first"], nodes["triangle_count"])
    expected = np.full(len(nodes), -1)

    def walk(index: int, depth: int) -> None:
        expected[index] = depth
        if nodes["triangle_count"][index] == 0:
            walk(int(nodes["left_or_first"][index]), depth + 1)
            walk(int(nodes["left_or_first"][index]) + 1, depth + 1)

    walk(0, 0)
    np.testing.assert_array_equal(levels, expected)
    assert (levels == 0).sum() == 1 and levels.max() > 1  # one root, and a tree with levels to pick


def test_unreachable_nodes_are_an_error():
    with pytest.raises(ValueError, match="node 3"):
        node_levels(np.array([1, 0, 0, 0]), np.array([0, 1, 1, 1]))


def test_box_edges_are_the_twelve_axis_parallel_edges():
    edges = box_edges(np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 2.0, 3.0]]))
    assert edges.shape == (12, 2, 3)
    lengths = np.abs(edges[:, 1] - edges[:, 0])
    # each edge runs along one axis; four edges per axis with that axis's extent
    assert np.all((lengths > 0).sum(axis=1) == 1)
    np.testing.assert_array_equal(np.sort(lengths.sum(axis=1)), [1] * 4 + [2] * 4 + [3] * 4)
    assert len({tuple(sorted(map(tuple, edge))) for edge in edges}) == 12
