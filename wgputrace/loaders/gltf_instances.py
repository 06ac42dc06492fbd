"""glTF nodes that share a mesh become instances of it: the mesh's primitives stored once as Shapes
in mesh space, each node an `Instance` placing them by its world matrix (`placed_meshes`).

A mesh is instanced where at least INSTANCE_MIN_REFERENCES nodes of the scene reference it; a node
whose world matrix mirrors or flattens (determinant <= 0) and a mesh with an emitting material
(the light sampler needs world-space emitters) keep today's flattened Shapes. A scene needs one
Shape of its own beside instances (the world's BVH is one top-level item), so a file whose every
mesh is instanced has its first instance flattened.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable

import numpy as np

from ..scene import SceneError, Shape
from ..scene.instances import Instance

# Two references: the second copy is the first that instancing saves.
INSTANCE_MIN_REFERENCES = 2


def placed_meshes(
    reader, placements: list[tuple[int, np.ndarray, str]], mesh_shapes: Callable[..., list[Shape]]
) -> tuple[list[Shape], list[Instance]]:
    """The Shapes and Instances of `placements` ((mesh index, world matrix, JSON path of the node) in
    the node tree's order); `mesh_shapes(mesh_index, world, where)` reads a mesh's primitives."""
    counts = Counter(mesh_index for mesh_index, _, _ in placements)
    shapes: list[Shape] = []
    instances: list[Instance] = []
    meshes: dict[int, list[Shape]] = {}
    for mesh_index, world, where in placements:
        if counts[mesh_index] >= INSTANCE_MIN_REFERENCES and mesh_index not in meshes:
            meshes[mesh_index] = mesh_shapes(mesh_index, np.eye(4), where)
        shared = meshes.get(mesh_index)
        with np.errstate(all="ignore"):
            determinant = np.linalg.det(world[:3, :3])
        if shared is None or not determinant > 0 or any(shape.material.emits() for shape in shared):
            shapes += mesh_shapes(mesh_index, world, where)
            continue
        for shape in shared:
            try:
                instances.append(Instance(f"{shape.name}@{where}", shape, world))
            except SceneError as error:
                raise reader.fail(where, str(error)) from None
    if instances and not shapes:
        shapes.append(instances.pop(0).flattened())
    return shapes, instances
