"""Shape generators with trac0r's parameters: planes, boxes and icospheres made of flat triangles.

Every generator places a unit shape with model = translate(position) . rotate(orientation) .
scale(size). `orientation` holds Euler angles in radians, applied about x, then y, then z
(R = Rz Ry Rx, right-handed). Triangles wind counter-clockwise seen from the side their normal
cross(v1 - v0, v2 - v0) points to, which is the outside of boxes and spheres.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .materials import Material

# Corner order and faces of trac0r's unit box (corners p1..p8 of its source, 0-based here), with
# the winding of three triangles that pointed inwards in trac0r fixed so every normal faces out.
_BOX_CORNERS = np.array(
    [
        [-0.5, 0.5, -0.5],
        [-0.5, -0.5, -0.5],
        [0.5, -0.5, -0.5],
        [0.5, 0.5, -0.5],
        [-0.5, 0.5, 0.5],
        [-0.5, -0.5, 0.5],
        [0.5, -0.5, 0.5],
        [0.5, 0.5, 0.5],
    ]
)
_BOX_FACES = np.array(
    [
        [1, 0, 2],
        [0, 3, 2],  # z = -0.5
        [3, 7, 2],
        [2, 7, 6],  # x = +0.5
        [0, 1, 5],
        [4, 0, 5],  # x = -0.5
        [4, 5, 7],
        [5, 6, 7],  # z = +0.5
        [4, 3, 0],
        [7, 3, 4],  # y = +0.5
        [1, 2, 5],
        [2, 6, 5],
    ]  # y = -0.5
)
# trac0r's unit plane lies in y = 0, its normal +y (listing 16 rotates it into place).
_PLANE_CORNERS = np.array([[-0.5, 0.0, 0.5], [-0.5, 0.0, -0.5], [0.5, 0.0, -0.5], [0.5, 0.0, 0.5]])
_PLANE_FACES = np.array([[1, 0, 2], [0, 3, 2]])

_GOLDEN = (1.0 + np.sqrt(5.0)) / 2.0
_ICOSAHEDRON_CORNERS = np.array(
    [
        [-1, _GOLDEN, 0],
        [1, _GOLDEN, 0],
        [-1, -_GOLDEN, 0],
        [1, -_GOLDEN, 0],
        [0, -1, _GOLDEN],
        [0, 1, _GOLDEN],
        [0, -1, -_GOLDEN],
        [0, 1, -_GOLDEN],
        [_GOLDEN, 0, -1],
        [_GOLDEN, 0, 1],
        [-_GOLDEN, 0, -1],
        [-_GOLDEN, 0, 1],
    ]
)
_ICOSAHEDRON_FACES = np.array(
    [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ]
)


@dataclass(eq=False)
class Shape:
    """A named group of flat triangles sharing one material."""

    name: str
    vertices: np.ndarray  # (n, 3, 3) float32: triangle, corner, xyz
    material: Material
    tags: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        vertices = np.ascontiguousarray(self.vertices, dtype=np.float32)
        if vertices.ndim != 3 or vertices.shape[1:] != (3, 3):
            raise ValueError(f"shape {self.name!r}: vertices must have shape (n, 3, 3), got {vertices.shape}")
        bad = np.flatnonzero(~np.isfinite(vertices).all(axis=(1, 2)))
        if bad.size:
            raise ValueError(f"shape {self.name!r}: triangle {int(bad[0])} has a NaN or infinite vertex")
        self.vertices = vertices

    @property
    def triangle_count(self) -> int:
        return int(self.vertices.shape[0])

    def transformed(self, matrix: np.ndarray) -> Shape:
        """This shape under an affine 4x4 or linear 3x3 matrix; a mirror keeps normals facing out."""
        return Shape(self.name, transform_points(self.vertices, matrix), self.material, dict(self.tags))


def euler_rotation(orientation) -> np.ndarray:
    """R = Rz Ry Rx for Euler angles (x, y, z) in radians."""
    ax, ay, az = (float(a) for a in orientation)
    cx, sx, cy, sy, cz, sz = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay), np.cos(az), np.sin(az)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def model_matrix(position, orientation, scale) -> np.ndarray:
    """translate(position) . rotate(orientation) . scale(scale) as a 4x4 matrix."""
    matrix = np.eye(4)
    matrix[:3, :3] = euler_rotation(orientation) @ np.diag(np.broadcast_to(np.asarray(scale, float), 3))
    matrix[:3, 3] = np.asarray(position, dtype=np.float64)
    return matrix


def transform_points(vertices: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Apply a 4x4 affine (or 3x3 linear) matrix to (n, 3, 3) triangles in float64, return float32.

    A matrix with negative determinant mirrors the geometry; swapping two corners keeps every
    triangle's normal on the same (outer) side.
    """
    matrix = np.asarray(matrix, dtype=np.float64)
    linear, offset = (matrix[:3, :3], matrix[:3, 3]) if matrix.shape == (4, 4) else (matrix, np.zeros(3))
    moved = vertices.astype(np.float64) @ linear.T + offset
    if np.linalg.det(linear) < 0:
        moved = moved[:, [0, 2, 1], :]
    return moved.astype(np.float32)


def _place(name: str, corners: np.ndarray, faces: np.ndarray, matrix: np.ndarray, material: Material) -> Shape:
    return Shape(name, transform_points(corners[faces], matrix), material)


def make_plane(position, orientation, size, material: Material, name: str = "plane") -> Shape:
    """Two triangles: a size[0] x size[1] rectangle in the local xz plane, rotated and moved."""
    width, depth = (float(s) for s in size)
    return _place(
        name, _PLANE_CORNERS, _PLANE_FACES, model_matrix(position, orientation, (width, 1.0, depth)), material
    )


def make_box(position, orientation, size, material: Material, name: str = "box") -> Shape:
    """Twelve triangles: a box of edge lengths `size` centred at `position`."""
    return _place(name, _BOX_CORNERS, _BOX_FACES, model_matrix(position, orientation, size), material)


def make_icosphere(
    position, orientation, radius: float, iterations: int, material: Material, name: str = "icosphere"
) -> Shape:
    """An icosahedron subdivided `iterations` times (20 * 4**iterations triangles), radius `radius`.

    Each subdivision splits a triangle (a, b, c) into (a, ab, ca), (b, bc, ab), (c, ca, bc),
    (ab, bc, ca), the new vertices pushed out to the unit sphere.
    """
    if iterations < 0:
        raise ValueError(f"icosphere {name!r}: iterations must be >= 0, got {iterations}")
    corners = _ICOSAHEDRON_CORNERS / np.linalg.norm(_ICOSAHEDRON_CORNERS, axis=1, keepdims=True)
    triangles = corners[_ICOSAHEDRON_FACES]
    for _ in range(iterations):
        a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
        ab, bc, ca = (_unit(a + b), _unit(b + c), _unit(c + a))
        triangles = np.stack(
            [np.stack(t, axis=1) for t in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))], axis=1
        ).reshape(-1, 3, 3)
    matrix = model_matrix(position, orientation, float(radius))
    return Shape(name, transform_points(triangles, matrix), material)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)
