"""Refitting a BVH whose triangles moved: bottom-up bounds updates of the affected nodes only, and
the tree's SAH cost kept up to date so callers can tell when a rebuild pays.

The topology never changes, only bounds, in place. A refit tree stays correct whatever the
motion, but its boxes grow where moved and unmoved triangles share a subtree: `degradation` (refit
SAH cost / cost when built) measures that, `python -m bench.refit_threshold` its render time.
"""

from __future__ import annotations

import numpy as np

from wgputrace.bvh.tree import BVH, box_surface_area

NO_PARENT = -1


class Refitter:
    """Moves triangles of one BVH and refits the nodes above them.

    `vertices_reordered` is (N, 3, 3) float32 in the BVH's triangle order (position k holds input
    triangle bvh.triangle_order[k]); the refitter keeps each position's bounds.
    """

    def __init__(self, bvh: BVH, vertices_reordered: np.ndarray) -> None:
        self.bvh = bvh
        self._triangle_min = vertices_reordered.min(axis=1)
        self._triangle_max = vertices_reordered.max(axis=1)
        count = bvh.triangle_count.astype(np.int64)
        first = bvh.left_or_first.astype(np.int64)
        leaves = np.flatnonzero(count > 0)
        self._leaf_of = np.empty(len(vertices_reordered), np.int64)
        self._leaf_of[_ranges(first[leaves], count[leaves])] = np.repeat(leaves, count[leaves])
        self._parent = np.full(bvh.node_count, NO_PARENT, np.int64)
        self._level = np.zeros(bvh.node_count, np.int64)
        if bvh.kind == "bvh":
            # children always have larger ids than their parent, so one pass in id order sees
            # every parent's level before its children's
            frontier = np.zeros(1, np.int64)
            while frontier.size:
                interior = frontier[count[frontier] == 0]
                children = (first[interior, None] + np.arange(2)).ravel()
                self._parent[children] = np.repeat(interior, 2)
                self._level[children] = np.repeat(self._level[interior] + 1, 2)
                frontier = children
        # SAH numerator: interior nodes weigh 1 (one box test), leaves their triangle count
        self._weight = np.where(count > 0, count, 1).astype(np.float64)
        self._area = box_surface_area(bvh.bounds_min, bvh.bounds_max)
        self._weighted_area = float(np.dot(self._weight, self._area))
        self.built_cost = self.cost

    @property
    def cost(self) -> float:
        """SAH cost with unit traversal and intersection costs; equals bvh.sah_cost() for kind "bvh"."""
        root_area = self._area[0]
        return self._weighted_area / root_area if root_area > 0 else float(self._weight.sum())

    @property
    def degradation(self) -> float:
        """Refit cost over the cost the tree had when built (1.0 = as good as built)."""
        return self.cost / self.built_cost if self.built_cost > 0 else 1.0

    def move(self, positions: np.ndarray, vertices: np.ndarray) -> np.ndarray:
        """Give the triangles at `positions` new corners (k, 3, 3); refit; return the ids of the
        nodes whose bounds changed, sorted."""
        positions = np.asarray(positions, np.int64)
        self._triangle_min[positions] = vertices.min(axis=1)
        self._triangle_max[positions] = vertices.max(axis=1)
        bvh = self.bvh
        leaves = np.unique(self._leaf_of[positions])
        first = bvh.left_or_first[leaves].astype(np.int64)
        count = bvh.triangle_count[leaves].astype(np.int64)
        members = _ranges(first, count)
        starts = np.cumsum(count) - count
        changed = [
            self._set_bounds(
                leaves,
                np.minimum.reduceat(self._triangle_min[members], starts, axis=0),
                np.maximum.reduceat(self._triangle_max[members], starts, axis=0),
            )
        ]
        # Every ancestor of a changed leaf, deepest level first: an interior node's bounds are
        # its children's union, so both children must be final before it.
        ancestors, current = [], changed[0]
        while current.size:
            current = np.unique(self._parent[current])
            current = current[current != NO_PARENT]
            ancestors.append(current)
        if ancestors:
            nodes = np.unique(np.concatenate(ancestors))
            levels = self._level[nodes]
            for level in np.unique(levels)[::-1]:
                group = nodes[levels == level]
                left = bvh.left_or_first[group].astype(np.int64)
                changed.append(
                    self._set_bounds(
                        group,
                        np.minimum(bvh.bounds_min[left], bvh.bounds_min[left + 1]),
                        np.maximum(bvh.bounds_max[left], bvh.bounds_max[left + 1]),
                    )
                )
        return np.unique(np.concatenate(changed))

    def _set_bounds(self, nodes: np.ndarray, bounds_min: np.ndarray, bounds_max: np.ndarray) -> np.ndarray:
        """Store new bounds, keep the SAH numerator current, return the nodes that changed."""
        bvh = self.bvh
        differs = np.any(bvh.bounds_min[nodes] != bounds_min, axis=1) | np.any(
            bvh.bounds_max[nodes] != bounds_max, axis=1
        )
        nodes = nodes[differs]
        bvh.bounds_min[nodes] = bounds_min[differs]
        bvh.bounds_max[nodes] = bounds_max[differs]
        area = box_surface_area(bounds_min[differs], bounds_max[differs])
        self._weighted_area += float(np.dot(self._weight[nodes], area - self._area[nodes]))
        self._area[nodes] = area
        return nodes


def _ranges(first: np.ndarray, count: np.ndarray) -> np.ndarray:
    """The concatenation of arange(first[i], first[i] + count[i]) over i."""
    starts = np.cumsum(count) - count
    return np.repeat(first - starts, count) + np.arange(int(count.sum()))
