"""A scene: shapes (triangles sharing a material), the materials they index, and a camera."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .camera import Camera
from .materials import Material
from .shapes import Shape


class SceneError(ValueError):
    """The scene cannot be rendered as it is (empty, inconsistent)."""


class DegenerateTrianglesWarning(UserWarning):
    """Zero-area triangles were dropped: they have no normal and must never be hit."""


def zero_area(vertices: np.ndarray) -> np.ndarray:
    """True where a triangle's corners coincide or lie on one line.

    The cross product is taken in float64 from the float32 corners, where it is exact for
    corners of similar magnitude, so exactly collinear corners give exactly zero. (On the GPU, f32
    rounding of a collinear triangle's edge functions can leave them all of one sign: a "hit" with
    a NaN normal. Dropping such triangles here keeps that test out of the intersection loop.)
    """
    v = vertices.astype(np.float64)
    return ~np.any(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]) != 0.0, axis=1)


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
        vertices = np.concatenate([shape.vertices for shape in self.shapes])
        material_index = np.repeat(np.array([slot[id(s.material)] for s in self.shapes], np.uint32), counts)
        shape_index = np.repeat(np.arange(len(self.shapes), dtype=np.uint32), counts)
        degenerate = zero_area(vertices)
        if degenerate.any():
            first = int(np.flatnonzero(degenerate)[0])
            shape = self.shapes[shape_index[first]]
            local = first - sum(counts[: shape_index[first]])
            warnings.warn(
                f"dropped {int(degenerate.sum())} zero-area triangles; the first is triangle {local} of "
                f"shape {shape.name!r}",
                DegenerateTrianglesWarning,
                stacklevel=2,
            )
            keep = ~degenerate
            vertices, material_index, shape_index = vertices[keep], material_index[keep], shape_index[keep]
            if len(vertices) == 0:
                raise SceneError("the scene has no triangles left after dropping zero-area ones")
        return TriangleArrays(vertices, material_index, shape_index, materials)
