"""Per-vertex shading attributes from per-corner ones: the vertices a mesh's triangles share.

Shapes keep their attributes per corner (n, 3, k), as loaders flatten a file's index buffer into
them; the GPU keeps them per vertex (TRIANGLE_VERTICES and VERTEX_NORMAL's siblings): a smooth
mesh shares each vertex among about six triangles, so it holds about a sixth of the records, and
12 bytes per triangle naming its vertices. Corners whose attributes are equal bit for bit become one
vertex, so a shared vertex of glTF or OBJ comes back as one and the GPU reads exactly the values
it read per corner: the images do not change. Vertices are numbered in the order of their first
corner, so an edit that keeps which corners are equal (a shape moved) keeps every index, and only
the moved vertices' records change.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..gpu.layout import TRIANGLE_VERTICES, GpuStruct

# Odd 64-bit multipliers, one per 32-bit word of a corner's key, for `_row_hashes`.
_HASH_MULTIPLIERS = np.random.default_rng(25).integers(0, 2**63, 64, dtype=np.uint64) * np.uint64(2) + np.uint64(1)


def shared_vertices(corners: Mapping[str, np.ndarray]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Each triangle's vertex indices (n, 3) uint32 and each attribute per vertex (v, k), from
    attributes per corner (n, 3, k) of 4-byte values (float32), all of the same n triangles."""
    values = list(corners.values())
    count = len(values[0])
    words = np.concatenate(
        [np.ascontiguousarray(v).reshape(3 * count, v.shape[-1]).view(np.uint32) for v in values], axis=1
    )
    first, inverse = _equal_rows(words)
    by_first = np.argsort(first)
    rank = np.empty_like(by_first)
    rank[by_first] = np.arange(len(by_first))
    indices = rank[inverse].reshape(count, 3).astype(np.uint32)
    corner_of_vertex = first[by_first]
    return indices, {name: v.reshape(3 * count, v.shape[-1])[corner_of_vertex] for name, v in corners.items()}


def _equal_rows(words: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For (m, k) uint32 rows: the first row of each set of equal ones, and each row's set. Sorting
    64-bit hashes of the rows rather than the rows (np.unique of their bytes) took 0.5-1.0 s against
    1.2 s for a 998,000-triangle sphere's normals and uvs on a quiet machine, a half to a quarter of
    the time on a busy one; rows are then compared with their set's first, and should two different
    rows share a hash, the rows themselves are sorted."""
    if not len(words):
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    hashes = _row_hashes(words)
    order = np.argsort(hashes)  # not a stable sort, which takes twice as long: `first` is a minimum
    new_set = hashes[order[1:]] != hashes[order[:-1]]
    inverse = np.empty(len(words), np.int64)
    inverse[order] = np.concatenate([[0], np.cumsum(new_set)])
    first = np.minimum.reduceat(order, np.flatnonzero(np.concatenate([[True], new_set])))
    if np.array_equal(words, words[first[inverse]]):
        return first, inverse
    keys = np.ascontiguousarray(words).view(np.dtype((np.void, words.shape[1] * 4))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    return first, inverse.ravel()


def _row_hashes(words: np.ndarray) -> np.ndarray:
    """A 64-bit hash of each (m, k) uint32 row (k at most len(_HASH_MULTIPLIERS)): a sum of its words
    times odd constants, mixed (wrapping uint64 arithmetic)."""
    hashes = np.zeros(len(words), np.uint64)
    for column in range(words.shape[1]):
        hashes += words[:, column].astype(np.uint64) * _HASH_MULTIPLIERS[column]
        hashes ^= hashes >> np.uint64(29)
    return hashes


def triangle_vertex_records(indices: np.ndarray) -> np.ndarray:
    """TRIANGLE_VERTICES records of (n, 3) vertex indices."""
    records = TRIANGLE_VERTICES.zeros(len(indices))
    records["v0"], records["v1"], records["v2"] = indices[:, 0], indices[:, 1], indices[:, 2]
    return records


def vertex_records(struct: GpuStruct, values: np.ndarray) -> np.ndarray:
    """Records of `struct` holding (v, k) values, its fields' components in field order."""
    records = struct.zeros(len(values))
    column = 0
    for name in struct.dtype.names:
        shape = struct.dtype[name].shape
        width = shape[0] if shape else 1
        records[name] = values[:, column] if not shape else values[:, column : column + width]
        column += width
    return records


def corner_values(triangle_vertices: np.ndarray, records: np.ndarray) -> np.ndarray:
    """The per-corner values (n, 3, k) of vertex `records` at TRIANGLE_VERTICES records, their
    fields' components in field order: what `shared_vertices` was given, back."""
    columns = [
        records[name].reshape(len(records), np.prod(records[name].shape[1:], dtype=int)) for name in records.dtype.names
    ]
    values = np.concatenate(columns, axis=1)
    return values[np.stack([triangle_vertices[f"v{k}"] for k in range(3)], axis=1)]
