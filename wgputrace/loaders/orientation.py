"""Winding closed meshes outwards: Glass takes the side opposite the triangle normal as inside,
and files often wind some triangles the other way (trac0r's boxes did).

A shape whose triangles, welded by exact corner position, form a closed surface (every edge shared
by exactly two triangles) is made consistent (neighbours traverse their shared edge in opposite
directions) and then turned so its enclosed volume is positive, component by component. Open or
non-manifold shapes (planes, cards, soups) are left as they are. A triangle is turned by swapping
its corners 1 and 2, as `Shape.world_vertices` does under a mirroring transform.
"""

from __future__ import annotations

import warnings
from collections import deque
from pathlib import Path

import numpy as np

from .errors import SceneLoadWarning


def orient_outwards(triangles: np.ndarray) -> np.ndarray:
    """Which of the (n, 3, 3) `triangles` to turn (bool per triangle); none unless they are closed."""
    count = len(triangles)
    turn = np.zeros(count, bool)
    if count < 4:  # the smallest closed surface, a tetrahedron
        return turn
    corner_id = _weld(triangles.reshape(-1, 3)).reshape(count, 3)
    start, end = corner_id.ravel(), corner_id[:, [1, 2, 0]].ravel()
    if np.any(start == end):  # a triangle with two coinciding corners is not part of a surface
        return turn
    key = np.minimum(start, end) * (corner_id.max() + 1) + np.maximum(start, end)
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    pairs_close = sorted_key[0::2].size == sorted_key[1::2].size and np.all(sorted_key[0::2] == sorted_key[1::2])
    if not pairs_close or np.any(sorted_key[2::2] == sorted_key[1:-1:2]):
        return turn  # some edge is used once (open) or more than twice (non-manifold)
    first, second = order[0::2], order[1::2]
    # both triangles run along their shared edge the same way: one of them is wound wrongly
    same_direction = start[first] == start[second]
    face_a, face_b = first // 3, second // 3
    if same_direction.any():
        turn = _consistent_turns(count, face_a, face_b, same_direction)
        if turn is None:
            return np.zeros(count, bool)  # not orientable (a Klein bottle): leave it be
    components = _components(count, face_a, face_b)
    volume = _signed_volumes(np.where(turn[:, None, None], triangles[:, [0, 2, 1]], triangles), components)
    return turn ^ (volume[components] < 0)


def wind_outwards(triangles: np.ndarray, path: Path, what: str, stacklevel: int) -> None:
    """Turn the inward-wound triangles of closed parts outwards in place, with a warning naming
    `what` (the mesh, or a shape of the file) and how many turned."""
    turn = orient_outwards(triangles)
    if turn.any():
        triangles[turn] = triangles[turn][:, [0, 2, 1]]
        warnings.warn(
            f"{path}: {what} is closed but {int(turn.sum())} of its {len(triangles)} triangles were wound "
            "inwards; turned them outwards (Glass needs the inside behind the normal)",
            SceneLoadWarning,
            stacklevel=stacklevel + 1,
        )


def _weld(points: np.ndarray) -> np.ndarray:
    """An id per (m, 3) float32 point, equal for equal points: a lexicographic sort of the bits
    (np.unique(axis=0) takes 7x as long on a million triangles)."""
    bits = (points + np.float32(0.0)).view(np.uint32)  # + 0 turns -0.0 into 0.0
    xy = (bits[:, 0].astype(np.uint64) << np.uint64(32)) | bits[:, 1]
    order = np.lexsort((bits[:, 2], xy))
    xy, z = xy[order], bits[order, 2]
    first = np.ones(len(order), bool)
    first[1:] = (xy[1:] != xy[:-1]) | (z[1:] != z[:-1])
    ids = np.empty(len(order), np.int64)
    ids[order] = np.cumsum(first) - 1
    return ids


def _consistent_turns(count: int, face_a, face_b, same_direction) -> np.ndarray | None:
    """Turns that make every shared edge run opposite ways, by breadth-first search from one
    triangle per component; None if no such turns exist."""
    neighbours, flips, offsets = _adjacency(count, face_a, face_b, same_direction)
    turn = np.zeros(count, bool)
    seen = np.zeros(count, bool)
    for seed in range(count):
        if seen[seed]:
            continue
        seen[seed] = True
        queue = deque([seed])
        while queue:
            face = queue.popleft()
            for k in range(offsets[face], offsets[face + 1]):
                other, wanted = neighbours[k], turn[face] ^ flips[k]
                if not seen[other]:
                    seen[other], turn[other] = True, wanted
                    queue.append(other)
                elif turn[other] != wanted:
                    return None
    return turn


def _adjacency(count: int, face_a, face_b, label):
    """Both directions of every (face_a, face_b, label) pair, grouped by face (CSR)."""
    source = np.concatenate([face_a, face_b])
    target = np.concatenate([face_b, face_a])
    labels = np.concatenate([label, label])
    order = np.argsort(source, kind="stable")
    offsets = np.concatenate([[0], np.cumsum(np.bincount(source, minlength=count))])
    return target[order].tolist(), labels[order].tolist(), offsets.tolist()


def _components(count: int, face_a: np.ndarray, face_b: np.ndarray) -> np.ndarray:
    """Connected component of every triangle, by label propagation with pointer jumping."""
    label = np.arange(count)
    while True:
        smaller = np.minimum(label[face_a], label[face_b])
        updated = label.copy()
        np.minimum.at(updated, face_a, smaller)
        np.minimum.at(updated, face_b, smaller)
        updated = updated[updated]  # jump to the label's own label: halves chains each round
        if np.array_equal(updated, label):
            break
        label = updated
    return np.unique(label, return_inverse=True)[1]


def _signed_volumes(triangles: np.ndarray, components: np.ndarray) -> np.ndarray:
    """Enclosed volume per component (divergence theorem), about each component's first corner so
    far-away meshes keep their digits."""
    corners = triangles.astype(np.float64)
    first = np.zeros(components.max() + 1, np.int64)
    first[components[::-1]] = np.arange(len(components))[::-1]
    corners -= corners[first[components], 0][:, None, :]
    volume = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])) / 6.0
    return np.bincount(components, weights=volume)
