"""Instances: a mesh (a Shape) stored once and placed in the world by many 4x4 transforms.

An `Instance` places its mesh's `world_vertices` (the mesh's own transform included) by its
`transform`, so `Instance(name, mesh, T)` draws what `mesh.transformed(T)` would, while the GPU keeps
the mesh's triangles once (`Scene.add_instance`; `render/instance_records.py` builds the two-level
acceleration structure). Assigning `transform` checks it and bumps `transform_version`: the renderer
then refits only the top level.
"""

from __future__ import annotations

import numpy as np

from .errors import SceneError
from .shapes import Shape, checked_transform


class Instance:
    """Shape `mesh` placed by `transform` (4x4 affine, float64, invertible, not mirroring: a mirror
    would turn the mesh's triangles inside out, which only a flattened copy can undo; flatten such
    placements with `mesh.transformed(T)`).

    `name` names it in errors; the mesh's material, normals, texture coordinates, tangents and
    vertex colours shade every instance alike.
    """

    def __init__(self, name: str, mesh: Shape, transform) -> None:
        if not isinstance(mesh, Shape):
            raise SceneError(f"instance {name!r}: mesh must be a Shape, got {type(mesh).__name__}")
        self.name, self.mesh = name, mesh
        self.transform_version = 0
        self._transform = checked_instance_transform(name, transform)

    def __repr__(self) -> str:
        return f"Instance({self.name!r} of {self.mesh.name!r})"

    @property
    def transform(self) -> np.ndarray:
        """Mesh to world, a read-only 4x4 affine float64 matrix (assign a new one to move the instance)."""
        return self._transform

    @transform.setter
    def transform(self, value) -> None:
        self._transform = checked_instance_transform(self.name, value)
        self.transform_version += 1

    def flattened(self) -> Shape:
        """The instance as a Shape of its own world triangles (what it draws, stored per triangle)."""
        shape = self.mesh.transformed(self._transform)
        shape.name = self.name
        return shape


def checked_instance_transform(name: str, value) -> np.ndarray:
    """`checked_transform` for an instance, which also refuses a mirror (negative determinant)."""
    matrix = checked_transform(name, value, kind="instance")
    determinant = np.linalg.det(matrix[:3, :3])
    if determinant < 0:
        raise SceneError(
            f"instance {name!r}: transform mirrors (determinant {determinant:.6g}): instances keep the mesh's "
            "winding; add mesh.transformed(transform) as a Shape instead"
        )
    return matrix
