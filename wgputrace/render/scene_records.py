"""A scene turned into GPU records: triangles in acceleration-structure order, nodes, materials.

The BVH is built and kept binary (`BVH`); the GPU gets it collapsed into 4-wide records
(`collapse`), the flat list its boxes as binary nodes. These are the pieces; SceneMirror puts them
together, for the renderer and (`scene_records`) for tests alike.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..bvh import BVH, build_bvh, build_flat
from ..bvh.wide import BUILD_MAX_DEPTH, WideBVH, collapse
from ..gpu.layout import (
    BVH_NODE,
    MATERIAL,
    TRIANGLE,
    WIDE_BVH_NODE,
)
from ..scene import Material, TriangleArrays

ACCELERATIONS = ("bvh", "flat")


@dataclass
class SceneRecords:
    triangles: np.ndarray  # TRIANGLE.dtype, in the order the acceleration structure references
    nodes: np.ndarray  # what the GPU traverses: WIDE_BVH_NODE.dtype for a BVH, BVH_NODE.dtype for the flat list
    materials: np.ndarray  # MATERIAL.dtype
    acceleration: BVH  # the canonical binary tree (or flat list)
    wide: WideBVH | None = None  # a BVH's 4-wide form, whose records `nodes` holds
    lights: np.ndarray | None = None  # LIGHT.dtype: the light sampler's alias table
    # the shading attributes per vertex and each triangle's vertices, by array name (SceneMirror.vertices)
    vertices: dict[str, np.ndarray] = field(default_factory=dict)


def material_records(materials: list[Material]) -> np.ndarray:
    """MATERIAL records: each material's kind and absorption, and the fields its class fills."""
    records = MATERIAL.zeros(len(materials))
    for record, material in zip(records, materials, strict=True):
        record["kind"], record["absorption"] = material.kind, material.absorption()
        material.fill_record(record)
    return records


def node_records(acceleration: BVH) -> np.ndarray:
    """The binary nodes as BVH_NODE records (the flat list's boxes on the GPU)."""
    nodes = BVH_NODE.zeros(acceleration.node_count)
    nodes["bounds_min"] = acceleration.bounds_min
    nodes["bounds_max"] = acceleration.bounds_max
    nodes["left_or_first"] = acceleration.left_or_first
    nodes["triangle_count"] = acceleration.triangle_count
    return nodes


def wide_node_records(wide: WideBVH, bvh: BVH) -> np.ndarray:
    """WIDE_BVH_NODE records of `wide`, the slots' boxes from `bvh`."""
    records = WIDE_BVH_NODE.zeros(wide.record_count)
    records["children"] = wide.refs
    set_wide_bounds(records, wide, bvh)
    return records


def set_wide_bounds(records: np.ndarray, wide: WideBVH, bvh: BVH, rows: np.ndarray | slice = slice(None)) -> None:
    """Regather the slot boxes of `records[rows]` from `bvh`'s nodes (after a refit)."""
    bounds_min, bounds_max = wide.slot_bounds(bvh, rows)
    for k, axis in enumerate("xyz"):
        records[f"min_{axis}"][rows] = bounds_min[..., k]
        records[f"max_{axis}"][rows] = bounds_max[..., k]


def gpu_node_records(acceleration: BVH) -> tuple[np.ndarray, WideBVH | None]:
    """What the GPU traverses: a BVH's 4-wide records and its wide form, or the flat list's boxes."""
    if acceleration.kind != "bvh":
        return node_records(acceleration), None
    wide = collapse(acceleration)
    return wide_node_records(wide, acceleration), wide


def build_acceleration(arrays: TriangleArrays, acceleration: str) -> BVH:
    if acceleration not in ACCELERATIONS:
        raise ValueError(f"acceleration must be one of {ACCELERATIONS}, got {acceleration!r}")
    if acceleration == "bvh":
        return build_bvh(arrays.vertices, max_depth=BUILD_MAX_DEPTH)
    return build_flat(arrays.vertices, arrays.shape_index)


def triangle_records(vertices: np.ndarray, material_index: np.ndarray) -> np.ndarray:
    """TRIANGLE records of (n, 3, 3) corners and their material indices, in the given order."""
    triangles = TRIANGLE.zeros(len(vertices))
    triangles["v0"], triangles["v1"], triangles["v2"] = vertices[:, 0], vertices[:, 1], vertices[:, 2]
    triangles["material"] = material_index
    return triangles
