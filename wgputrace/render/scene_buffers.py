"""A scene turned into GPU records: triangles in acceleration-structure order, nodes, materials."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bvh import BVH, build_bvh, build_flat
from ..gpu.layout import BVH_NODE, MATERIAL, TRIANGLE
from ..gpu.pipeline import BVH_STACK_SIZE
from ..scene import Material, Scene, TriangleArrays

ACCELERATIONS = ("bvh", "flat")


@dataclass
class SceneRecords:
    triangles: np.ndarray  # TRIANGLE.dtype, in the order the acceleration structure references
    nodes: np.ndarray  # BVH_NODE.dtype
    materials: np.ndarray  # MATERIAL.dtype
    acceleration: BVH


def material_records(materials: list[Material]) -> np.ndarray:
    records = MATERIAL.zeros(len(materials))
    for record, material in zip(records, materials, strict=False):
        color, alpha, ior = material.gpu_parameters()
        record["color"], record["kind"], record["alpha"], record["ior"] = color, int(material.kind), alpha, ior
    return records


def node_records(acceleration: BVH) -> np.ndarray:
    nodes = BVH_NODE.zeros(acceleration.node_count)
    nodes["bounds_min"] = acceleration.bounds_min
    nodes["bounds_max"] = acceleration.bounds_max
    nodes["left_or_first"] = acceleration.left_or_first
    nodes["triangle_count"] = acceleration.triangle_count
    return nodes


def build_acceleration(arrays: TriangleArrays, acceleration: str) -> BVH:
    if acceleration not in ACCELERATIONS:
        raise ValueError(f"acceleration must be one of {ACCELERATIONS}, got {acceleration!r}")
    if acceleration == "bvh":
        return build_bvh(arrays.vertices, max_depth=BVH_STACK_SIZE)
    return build_flat(arrays.vertices, arrays.shape_index)


def triangle_records(vertices: np.ndarray, material_index: np.ndarray) -> np.ndarray:
    """TRIANGLE records of (n, 3, 3) corners and their material indices, in the given order."""
    triangles = TRIANGLE.zeros(len(vertices))
    triangles["v0"], triangles["v1"], triangles["v2"] = vertices[:, 0], vertices[:, 1], vertices[:, 2]
    triangles["material"] = material_index
    return triangles


def scene_records(scene: Scene, acceleration: str = "bvh") -> SceneRecords:
    arrays = scene.arrays()
    structure = build_acceleration(arrays, acceleration)
    order = structure.triangle_order
    triangles = triangle_records(arrays.vertices[order], arrays.material_index[order])
    return SceneRecords(triangles, node_records(structure), material_records(arrays.materials), structure)
