"""The two-level acceleration structure of a scene with instances, as GPU records.

A bottom-level BVH per unique mesh (built once, its triangles in object space) and a top-level BVH
over the world boxes of the instances, whose leaves are INSTANCE records (matrices, the mesh's
root record, the instance's slot). The scene's own shapes keep their world BVH (SceneMirror's) and
take part as one more top-level item with slot 0, so their triangles keep their indices.

Record order on the GPU, which `SceneMirror.arrays` assembles: the nodes are the top level's
records (record 0, where traversal starts), then the world BVH's, then each mesh's; the triangles
are the world's, then each mesh's. A triangle's hit word is `slot << triangle_bits | index`
(`traverse_instanced.wgsl`), so the world's words are their indices and the light table, which
holds world triangles only, needs nothing new.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bvh import BVH, Refitter, build_bvh
from ..bvh.wide import BUILD_MAX_DEPTH, WIDE_COUNT_BITS, WIDE_EMPTY, WIDE_FIRST_LIMIT, WIDE_LEAF, WideBVH
from ..gpu.layout import INSTANCE
from ..scene import Scene, SceneError, Shape
from ..scene.instances import Instance
from ..scene.scene import zero_area
from ..scene.shapes import corner_colors, corner_normals, corner_uvs
from ..scene.tangents import corner_tangents
from .scene_records import gpu_node_records, set_wide_bounds, triangle_records

# A hit word's bits: slot and triangle index share them (`InstanceRecords.triangle_bits`)
WORD_BITS = 32
# Rebuild the top level when refits have made its SAH cost this many times what it was built with:
# the world BVH's REBUILD_DEGRADATION (bench.refit_threshold's measurement), whose rebuild the
# mirror then does with it.
TOP_REBUILD_DEGRADATION = 1.2


@dataclass
class MeshTree:
    """One mesh's bottom level: its BVH, the local index of each kept triangle in BVH order, and where
    its triangles and records start in the GPU arrays."""

    mesh: Shape
    bvh: BVH
    wide: WideBVH
    nodes: np.ndarray  # WIDE_BVH_NODE records, references still local
    local_index: np.ndarray
    first_triangle: int = 0
    first_record: int = 0


def joined(parts: list[np.ndarray]) -> np.ndarray:
    """GPU records of `parts` one after another, their dtype (its padding) kept as np.concatenate
    of structured arrays does not."""
    records = np.zeros(sum(len(part) for part in parts), parts[0].dtype)
    start = 0
    for part in parts:
        records[start : start + len(part)] = part
        start += len(part)
    return records


def shifted_references(refs: np.ndarray, record_offset: int, triangle_offset: int) -> np.ndarray:
    """Wide child words moved to start at `record_offset` (interior) and `triangle_offset` (leaves)."""
    refs = refs.astype(np.uint32)
    leaf = (refs & WIDE_LEAF) != 0
    empty = refs == WIDE_EMPTY
    first = ((refs & ~np.uint32(WIDE_LEAF)) >> WIDE_COUNT_BITS).astype(np.int64) + triangle_offset
    if leaf.any() and first[leaf & ~empty].max(initial=0) >= WIDE_FIRST_LIMIT:
        raise SceneError(f"instanced meshes hold more triangles than a leaf reference addresses ({WIDE_FIRST_LIMIT:,})")
    count = refs & np.uint32((1 << WIDE_COUNT_BITS) - 1)
    moved_leaf = np.uint32(WIDE_LEAF) | (first.astype(np.uint32) << WIDE_COUNT_BITS) | count
    return np.where(empty, refs, np.where(leaf, moved_leaf, refs + np.uint32(record_offset))).astype(np.uint32)


def box_triangles(low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Boxes (n, 3) as (n, 3, 3) float32 'triangles' whose bounds are the boxes and whose centroid
    their centre, so the triangle BVH builder and Refitter serve the top level unchanged."""
    return np.stack([low, high, 0.5 * (low + high)], axis=1).astype(np.float32)


def outward_float32(low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """float64 box corners as float32 rounded outward, so the box still holds what it bounds."""
    low32, high32 = low.astype(np.float32), high.astype(np.float32)
    low32 = np.where(low32 > low, np.nextafter(low32, np.float32(-np.inf)), low32)
    high32 = np.where(high32 < high, np.nextafter(high32, np.float32(np.inf)), high32)
    return low32, high32


def placed_box(tree: MeshTree, transform: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The world box (float32, outward) around `tree`'s root box placed by `transform`."""
    low, high = tree.bvh.bounds_min[0].astype(np.float64), tree.bvh.bounds_max[0].astype(np.float64)
    corners = np.array([[(high if (k >> axis) & 1 else low)[axis] for axis in range(3)] for k in range(8)])
    world = corners @ transform[:3, :3].T + transform[:3, 3]
    return outward_float32(world.min(axis=0), world.max(axis=0))


def _check_emission(instance: Instance) -> None:
    material = instance.mesh.material
    if material.emits() or max(material.surface_emission()) > 0:
        raise SceneError(
            f"instance {instance.name!r}: its mesh {instance.mesh.name!r} emits light, and the light sampler "
            "needs emitters in world space: add instance.flattened() as a Shape instead"
        )


def mesh_tree(mesh: Shape) -> MeshTree:
    """The bottom level of `mesh` (its world vertices, zero-area triangles left out)."""
    vertices = mesh.world_vertices
    kept = np.flatnonzero(~zero_area(vertices))
    if kept.size == 0:
        raise SceneError(f"instanced mesh {mesh.name!r} has no triangles of non-zero area")
    bvh = build_bvh(vertices[kept], max_depth=BUILD_MAX_DEPTH)
    nodes, wide = gpu_node_records(bvh)
    return MeshTree(mesh, bvh, wide, nodes, kept[bvh.triangle_order].astype(np.uint32))


class InstanceRecords:
    """The GPU records of `scene.instances` beside a world BVH (`world_bvh`, its wide form
    `world_wide`, `world_triangle_count` triangles), and what edits to their transforms need.

    `material_slot` maps id(material) to its index in the scene's material list.
    """

    def __init__(
        self, scene: Scene, world_bvh: BVH, world_wide: WideBVH, world_triangle_count: int, material_slot: dict
    ) -> None:
        self.instances = list(scene.instances)
        for instance in self.instances:
            _check_emission(instance)
        trees: dict[int, MeshTree] = {}
        for instance in self.instances:
            if id(instance.mesh) not in trees:
                trees[id(instance.mesh)] = mesh_tree(instance.mesh)
        self.trees = list(trees.values())
        self._tree_of = [trees[id(instance.mesh)] for instance in self.instances]
        self.world_bvh, self.world_wide = world_bvh, world_wide
        self.world_triangle_count = world_triangle_count
        first = world_triangle_count
        for tree in self.trees:
            tree.first_triangle, first = first, first + len(tree.local_index)
        self.triangle_count = first
        items = len(self.instances) + 1
        self.triangle_bits = WORD_BITS - items.bit_length()
        if self.triangle_count >= (1 << self.triangle_bits) - 1:
            raise SceneError(
                f"{len(self.instances):,} instances and {self.triangle_count:,} stored triangles do not fit a {WORD_BITS}-bit "
                f"hit word ({WORD_BITS - self.triangle_bits} bits of instance, {self.triangle_bits} of triangle): "
                "flatten some instances"
            )
        self.triangles = joined(
            [
                triangle_records(
                    tree.mesh.world_vertices[tree.local_index],
                    np.full(len(tree.local_index), material_slot[id(tree.mesh.material)], np.uint32),
                )
                for tree in self.trees
            ]
        )
        self._build_top()

    def _build_top(self) -> None:
        low, high = self._item_boxes()
        self.top = build_bvh(box_triangles(low, high), max_depth=BUILD_MAX_DEPTH)
        self.top_refitter = Refitter(self.top, box_triangles(low, high)[self.top.triangle_order])
        self.top_nodes, self.top_wide = gpu_node_records(self.top)
        self.top_records = self.top_wide.record_count
        first = self.top_records + self.world_wide.record_count
        for tree in self.trees:
            tree.first_record, first = first, first + tree.wide.record_count
        self.mesh_nodes = joined(
            [self._shifted(tree.nodes, tree.first_record, tree.first_triangle) for tree in self.trees]
        )
        self._position = np.empty(len(self.top.triangle_order), np.int64)
        self._position[self.top.triangle_order] = np.arange(len(self._position))
        self.records = INSTANCE.zeros(len(self._position))
        self.records["root"][self._position[0]] = self.top_records
        self._fill(np.arange(1, len(self._position)))
        self.records["slot"] = np.arange(1, len(self._position) + 1, dtype=np.uint32)
        self.records["slot"][self._position[0]] = 0
        for row in range(3):  # never read (slot 0 is the world), kept what they mean
            self.records[f"object_to_world{row}"][self._position[0]] = np.eye(4)[row]
            self.records[f"world_to_object{row}"][self._position[0]] = np.eye(4)[row]

    def _shifted(self, nodes: np.ndarray, record_offset: int, triangle_offset: int) -> np.ndarray:
        shifted = nodes.copy()
        shifted["children"] = shifted_references(nodes["children"], record_offset, triangle_offset)
        return shifted

    def _item_boxes(self) -> tuple[np.ndarray, np.ndarray]:
        """The world boxes of the top level's items: the world BVH's root box, then each instance's."""
        boxes = [(self.world_bvh.bounds_min[0], self.world_bvh.bounds_max[0])]
        boxes += [
            placed_box(tree, instance.transform) for instance, tree in zip(self.instances, self._tree_of, strict=True)
        ]
        return np.array([low for low, _ in boxes], np.float32), np.array([high for _, high in boxes], np.float32)

    def _fill(self, items: np.ndarray) -> None:
        """The INSTANCE records of top-level `items` (instances are items 1...)."""
        for item in items:
            instance, tree = self.instances[item - 1], self._tree_of[item - 1]
            record = self.records[self._position[item]]
            inverse = np.linalg.inv(instance.transform)
            for row in range(3):
                record[f"object_to_world{row}"] = instance.transform[row]
                record[f"world_to_object{row}"] = inverse[row]
            record["root"] = tree.first_record

    @property
    def stack_entries(self) -> int:
        """The traversal stack a ray needs: the top level's, and below it the deepest bottom level's."""
        return self.top_wide.max_stack + max([self.world_wide.max_stack, *(tree.wide.max_stack for tree in self.trees)])

    def world_nodes(self, world_nodes: np.ndarray) -> np.ndarray:
        """The world BVH's wide records as they sit after the top level's."""
        return self._shifted(world_nodes, self.top_records, 0)

    def nodes(self, world_nodes: np.ndarray) -> np.ndarray:
        """Every wide record the GPU traverses: the top level, the world BVH, each mesh."""
        return joined([self.top_nodes, self.world_nodes(world_nodes), self.mesh_nodes])

    def refit(self) -> bool:
        """Bring the top level (`top_nodes`, `records`) up to date with the instances' transforms and
        the world BVH's root box, refitting its boxes; False where the refit top level got slow enough
        that only a rebuild will do."""
        low, high = self._item_boxes()
        touched = self.top_refitter.move(self._position, box_triangles(low, high))
        if self.top_refitter.degradation > TOP_REBUILD_DEGRADATION:
            return False
        moved = np.zeros(self.top.node_count + 1, bool)
        moved[touched] = True
        set_wide_bounds(
            self.top_nodes, self.top_wide, self.top, np.flatnonzero(moved[self.top_wide.slot_node].any(axis=1))
        )
        self._fill(np.arange(1, len(self._position)))
        return True

    def corner_values(self, kind: str) -> np.ndarray | None:
        """The meshes' corner `kind` ("normals", "uvs", "tangents", "colors") in GPU order, object
        space; None where no mesh has any (tangents: MikkTSpace's where a mesh has uvs)."""
        gather = {"normals": corner_normals, "uvs": corner_uvs, "colors": corner_colors, "tangents": corner_tangents}
        parts = [
            gather[kind]([tree.mesh], np.zeros(len(tree.local_index), np.uint32), tree.local_index)
            for tree in self.trees
        ]
        if all(part is None for part in parts):
            return None
        width = next(part.shape[-1] for part in parts if part is not None)
        missing = 1.0 if kind == "colors" else 0.0
        return np.concatenate(
            [
                np.full((len(tree.local_index), 3, width), missing, np.float32) if part is None else part
                for tree, part in zip(self.trees, parts, strict=True)
            ]
        )
