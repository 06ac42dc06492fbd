"""Moving objects' motion vectors: for each shape and instance, what takes its points from where
they are now to where they were at the previous frame (OBJECT_MOTION records, read by the G-buffer's
`object_motion` in shaders/integrators/gbuffer.wgsl), and each world triangle's record.

An object whose transform changed since the last frame (Shape.transform, Instance.transform, or an
instanced mesh's own transform) gets its previous transform times the inverse of its current one;
every other object the identity, exactly, so what did not move has motion 0 exactly. A shape whose
`vertices` were replaced has no transform to follow: its new triangles have no motion of their own.

Record order: one per instance record (`InstanceRecords.records`, so an instance's is its hit word's
slot - 1; the scene's own shapes' item has the identity), then one per shape; `triangle_objects`
holds each world triangle's (in BVH order). Both are record arrays of the pixels group, kept by
GpuRecords and bound only in the G-buffer variant.
"""

from __future__ import annotations

import numpy as np

from ..gpu.layout import OBJECT_MOTION
from ..scene import Scene
from .scene_mirror import SceneMirror, changed_rows

TRIANGLE_OBJECTS, OBJECT_MOTIONS = "triangle objects", "object motions"
# the object id of the instances' top-level item that stands for the scene's own shapes (never read:
# their triangles name their shape's record)
_WORLD_ITEM = np.uint32(0xFFFFFFFF)
_IDENTITY_ROWS = np.eye(4)[:3]


def _placements(scene: Scene) -> list[tuple]:
    """Each object's transforms as arrays (a shape's; an instance's and its mesh's), shapes first:
    transforms are replaced on assignment, never edited in place, so the same arrays mean no move."""
    return [(shape, shape.transform) for shape in scene.shapes] + [
        (instance, instance.transform, instance.mesh.transform) for instance in scene.instances
    ]


def _matrix(placement: tuple) -> np.ndarray:
    """The object's transform from its own coordinates to the world (an instance's times its mesh's)."""
    matrix = placement[1]
    for inner in placement[2:]:
        matrix = matrix @ inner
    return matrix


class ObjectMotion:
    """The motion records of a scene's objects since the last frame (`frame_done`), brought up to
    date with the scene and its mirror by `update`; `arrays` holds them by record-array name."""

    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}
        # each object's placement at the last frame, by id() (the object itself kept, so an id
        # reused by a new object is not mistaken for it)
        self._previous: dict[int, tuple] = {}
        self._rebuilds = -1

    def update(self, scene: Scene, mirror: SceneMirror) -> dict[str, np.ndarray]:
        """The records for `scene` as it is now (after `mirror.update()`); returns their changed rows."""
        shapes = len(scene.shapes)
        # the top-level item of each instance record: 0 the shapes', i > 0 instance i - 1
        instancing = mirror.instancing
        items = np.zeros(0, np.int64) if instancing is None else instancing.top.triangle_order.astype(np.int64)
        motions = OBJECT_MOTION.zeros(len(items) + shapes)
        objects = np.concatenate([np.where(items > 0, shapes + items - 1, -1), np.arange(shapes)])
        motions["object"] = np.where(objects >= 0, objects, _WORLD_ITEM).astype(np.uint32)
        moved = np.tile(_IDENTITY_ROWS, (len(motions), 1, 1))
        record_of_object = np.empty(shapes + len(scene.instances), np.int64)
        record_of_object[objects[objects >= 0]] = np.flatnonzero(objects >= 0)
        for number, placement in enumerate(_placements(scene)):
            before = self._previous.get(id(placement[0]))
            if before is None or before[0] is not placement[0]:
                continue
            if all(a is b for a, b in zip(before[1:], placement[1:], strict=True)):
                continue
            moved[record_of_object[number]] = (_matrix(before) @ np.linalg.inv(_matrix(placement)))[:3]
        for row in range(3):
            motions[f"previous_from_current{row}"] = moved[:, row]
        new = {OBJECT_MOTIONS: motions}
        if mirror.rebuilds != self._rebuilds or TRIANGLE_OBJECTS not in self.arrays:
            new[TRIANGLE_OBJECTS] = (mirror.triangle_shapes + np.uint32(len(items))).astype(np.uint32)
            self._rebuilds = mirror.rebuilds
        changes = {
            name: changed_rows(self.arrays[name], records) if name in self.arrays else np.arange(len(records))
            for name, records in new.items()
        }
        self.arrays |= new
        return {name: rows for name, rows in changes.items() if rows.size}

    def frame_done(self, scene: Scene) -> None:
        """The scene as it is now is the previous frame's for the next `update`."""
        self._previous = {id(placement[0]): placement for placement in _placements(scene)}
