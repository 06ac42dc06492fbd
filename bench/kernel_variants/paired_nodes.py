"""Experiment (bench/kernel_profile.py, variant paired_nodes; measured slower than plain node texels,
see bench/README.md): the binary BVH with each interior node's two child boxes stored together.

The canonical tree (wgputrace/bvh/tree.py) stores a node's own box in the node, so a traversal step reads the node
it stands on (for its child index or triangle range) and then both children (for their boxes). Here
one record holds both children of an interior node: their boxes, and for each child either the
record of its own children (an interior child, count 0) or its triangle range (a leaf, count > 0).
A step reads one record and tests both boxes. Record 0 holds the root alone (side a; side b stays
zero and is never read). Interior node i's children are record 1 + (the number of interior nodes
before i), so there is one record per interior node plus one, the same bytes as the canonical
nodes: each box is stored once, in its parent.
"""

from __future__ import annotations

import numpy as np

from wgputrace.bvh.tree import BVH
from wgputrace.gpu.layout import GpuStruct

PAIRED_NODE = GpuStruct(
    "PairedNode",
    (
        ("a_min", "vec3<f32>"),
        ("a_ref", "u32"),
        ("a_max", "vec3<f32>"),
        ("a_count", "u32"),
        ("b_min", "vec3<f32>"),
        ("b_ref", "u32"),
        ("b_max", "vec3<f32>"),
        ("b_count", "u32"),
    ),
    "Both children of a BVH node: box, and count 0 -> ref = its children's record, else first triangle.",
)

SIDES = ("a", "b")


def interior_records(bvh: BVH) -> np.ndarray:
    """Per node: the record holding its children, or -1 for a leaf."""
    interior = bvh.triangle_count == 0
    return np.where(interior, np.cumsum(interior) - interior + 1, -1)


def paired_fields(bvh: BVH) -> dict[str, np.ndarray]:
    """The records' fields (a_min, a_ref, a_max, a_count, b_min, ...) as arrays of one row per record."""
    if bvh.kind != "bvh":
        raise ValueError(f"paired records need a tree (kind 'bvh'), got kind {bvh.kind!r}")
    records = interior_records(bvh)
    interior = np.flatnonzero(records >= 0)
    count = 1 + interior.size
    left = bvh.left_or_first[interior].astype(np.int64)
    fields: dict[str, np.ndarray] = {}
    for side, children in zip(SIDES, (left, left + 1), strict=True):
        # record 0's side a is the root; its side b stays zero
        nodes = np.concatenate([[0], children]) if side == "a" else children
        rows = slice(0, count) if side == "a" else slice(1, count)
        child_interior = records[nodes] >= 0
        fields[f"{side}_min"] = np.zeros((count, 3), np.float32)
        fields[f"{side}_max"] = np.zeros((count, 3), np.float32)
        fields[f"{side}_ref"] = np.zeros(count, np.uint32)
        fields[f"{side}_count"] = np.zeros(count, np.uint32)
        fields[f"{side}_min"][rows] = bvh.bounds_min[nodes]
        fields[f"{side}_max"][rows] = bvh.bounds_max[nodes]
        fields[f"{side}_ref"][rows] = np.where(child_interior, records[nodes], bvh.left_or_first[nodes])
        fields[f"{side}_count"][rows] = bvh.triangle_count[nodes]
    return fields
