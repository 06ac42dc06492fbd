"""A scene turned into GPU records: triangles in acceleration-structure order, nodes, materials.

The BVH is built and kept binary (`BVH`); the GPU gets it collapsed into 4-wide records
(`collapse`), the flat list its boxes as binary nodes. These are the pieces; SceneMirror puts them
together, for the renderer and (`scene_records`) for tests alike.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bvh import BVH, build_bvh, build_flat
from ..bvh.wide import BUILD_MAX_DEPTH, WideBVH, collapse
from ..gpu.layout import (
    BVH_NODE,
    CORNER_ATTRIBUTES,
    CORNER_COLORS,
    CORNER_TANGENTS,
    CORNER_UVS,
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
    corner_attributes: np.ndarray | None = None  # CORNER_ATTRIBUTES.dtype like `triangles`; None: no normals
    lights: np.ndarray | None = None  # LIGHT.dtype: the light sampler's alias table


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


def corner_attribute_records(normals: np.ndarray) -> np.ndarray:
    """CORNER_ATTRIBUTES records of (n, 3, 3) corner normals, in the given order."""
    records = CORNER_ATTRIBUTES.zeros(len(normals))
    records["normal0"], records["normal1"], records["normal2"] = normals[:, 0], normals[:, 1], normals[:, 2]
    return records


def corner_uv_records(uvs: np.ndarray) -> np.ndarray:
    """CORNER_UVS records of (n, 3, 2) corner texture coordinates, in the given order."""
    records = CORNER_UVS.zeros(len(uvs))
    records["uv0"], records["uv1"], records["uv2"] = uvs[:, 0], uvs[:, 1], uvs[:, 2]
    return records


def corner_tangent_records(tangents: np.ndarray) -> np.ndarray:
    """CORNER_TANGENTS records of (n, 3, 4) corner tangents, in the given order."""
    records = CORNER_TANGENTS.zeros(len(tangents))
    records["tangent0"], records["tangent1"], records["tangent2"] = tangents[:, 0], tangents[:, 1], tangents[:, 2]
    return records


def corner_color_records(colors: np.ndarray) -> np.ndarray:
    """CORNER_COLORS records of (n, 3, 4) corner vertex colours, in the given order."""
    records = CORNER_COLORS.zeros(len(colors))
    records["color0"], records["color1"], records["color2"] = colors[:, 0], colors[:, 1], colors[:, 2]
    return records
