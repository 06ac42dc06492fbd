"""A scene: shapes (triangles sharing a material), the materials they index, and a camera."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .camera import Camera
from .materials import Material
from .shapes import Shape


class SceneError(ValueError):
    """The scene cannot be rendered as it is (empty, inconsistent)."""


@dataclass
class TriangleArrays:
    """The scene flattened for the GPU: each triangle points at its material, never copies it."""

    vertices: np.ndarray  # (n, 3, 3) float32
    material_index: np.ndarray  # (n,) uint32 into `materials`
    shape_index: np.ndarray  # (n,) uint32 into the scene's shapes
    materials: list[Material]


@dataclass
class Scene:
    shapes: list[Shape] = field(default_factory=list)
    camera: Camera = field(default_factory=Camera)

    def add(self, *shapes: Shape) -> Scene:
        self.shapes.extend(shapes)
        return self

    @property
    def materials(self) -> list[Material]:
        """Distinct materials in order of first use."""
        seen: dict[int, Material] = {}
        for shape in self.shapes:
            seen.setdefault(id(shape.material), shape.material)
        return list(seen.values())

    @property
    def triangle_count(self) -> int:
        return sum(shape.triangle_count for shape in self.shapes)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        vertices = self.arrays().vertices.reshape(-1, 3)
        return vertices.min(axis=0), vertices.max(axis=0)

    def arrays(self) -> TriangleArrays:
        if self.triangle_count == 0:
            raise SceneError("the scene has no triangles: add at least one shape")
        materials = self.materials
        slot = {id(material): index for index, material in enumerate(materials)}
        counts = [shape.triangle_count for shape in self.shapes]
        return TriangleArrays(
            vertices=np.concatenate([shape.vertices for shape in self.shapes]),
            material_index=np.repeat(np.array([slot[id(s.material)] for s in self.shapes], np.uint32), counts),
            shape_index=np.repeat(np.arange(len(self.shapes), dtype=np.uint32), counts),
            materials=materials,
        )
