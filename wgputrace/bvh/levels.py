"""Levels of a BVH and the edges of its boxes: what the viewer draws to show a tree level."""

from __future__ import annotations

import numpy as np

# Corner k of a box has coordinate axis a at max when bit a of k is set; an edge joins corners
# that differ in one bit.
_EDGES = np.array([(k, k | (1 << axis)) for axis in range(3) for k in range(8) if not k & (1 << axis)])


def node_levels(left_or_first: np.ndarray, triangle_count: np.ndarray) -> np.ndarray:
    """Depth of every node below the root (root: 0), for the canonical layout (interior node i:
    triangle_count 0, children left_or_first[i] and left_or_first[i] + 1)."""
    levels = np.full(len(left_or_first), -1, dtype=np.int64)
    if len(levels) == 0:
        return levels
    current = np.array([0])
    depth = 0
    while len(current):
        levels[current] = depth
        interior = current[triangle_count[current] == 0]
        left = left_or_first[interior].astype(np.int64)
        current = np.concatenate([left, left + 1])
        depth += 1
    if np.any(levels < 0):
        raise ValueError(f"node {int(np.flatnonzero(levels < 0)[0])} is not reachable from the root")
    return levels


def box_edges(bounds_min: np.ndarray, bounds_max: np.ndarray) -> np.ndarray:
    """The 12 edges of each box as (boxes * 12, 2, 3) endpoints."""
    low, high = np.asarray(bounds_min, np.float32), np.asarray(bounds_max, np.float32)
    bits = (np.arange(8)[:, None] >> np.arange(3)[None, :]) & 1  # (corner, axis)
    corners = np.where(bits[None, :, :] == 1, high[:, None, :], low[:, None, :])  # (box, corner, axis)
    return corners[:, _EDGES].reshape(-1, 2, 3)
