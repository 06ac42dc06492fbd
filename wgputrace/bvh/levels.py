"""Levels of a BVH and the edges of its boxes: what the viewer draws to show a tree level."""

from __future__ import annotations

import numpy as np

# Corner k of a box has coordinate axis a at max when bit a of k is set; an edge joins corners
# that differ in one bit.
_EDGES = np.array([(k, k | (1 << axis)) for axis in range(3) for k in range(8) if not k & (1 << axis)])


def breadth_first_levels(left_or_first: np.ndarray, triangle_count: np.ndarray) -> list[np.ndarray]:
    """Node ids of each level of the canonical layout (interior node i: triangle_count 0, children
    left_or_first[i] and left_or_first[i] + 1), from the root's level down; each interior node's
    children together, in their parents' order. This is the order build_bvh numbers nodes in."""
    levels = []
    current = np.zeros(min(len(left_or_first), 1), np.int64)
    while current.size:
        levels.append(current)
        interior = current[triangle_count[current] == 0]
        current = (left_or_first[interior].astype(np.int64)[:, None] + np.arange(2)).ravel()
    return levels


def node_levels(left_or_first: np.ndarray, triangle_count: np.ndarray) -> np.ndarray:
    """Depth of every node below the root (root: 0), for the canonical layout."""
    levels = np.full(len(left_or_first), -1, dtype=np.int64)
    for depth, nodes in enumerate(breadth_first_levels(left_or_first, triangle_count)):
        levels[nodes] = depth
    if np.any(levels < 0):
        raise ValueError(f"node {int(np.flatnonzero(levels < 0)[0])} is not reachable from the root")
    return levels


def box_edges(bounds_min: np.ndarray, bounds_max: np.ndarray) -> np.ndarray:
    """The 12 edges of each box as (boxes * 12, 2, 3) endpoints."""
    low, high = np.asarray(bounds_min, np.float32), np.asarray(bounds_max, np.float32)
    bits = (np.arange(8)[:, None] >> np.arange(3)[None, :]) & 1  # (corner, axis)
    corners = np.where(bits[None, :, :] == 1, high[:, None, :], low[:, None, :])  # (box, corner, axis)
    return corners[:, _EDGES].reshape(-1, 2, 3)
