"""Shape generators with trac0r's parameters: planes, boxes and icospheres made of flat triangles.

A shape may carry per-corner attributes beside its corners, each an array (n, 3, k) in the
triangles' order: `normals` (k = 3) for smooth shading, `uvs` (k = 2) texture coordinates,
`tangents` (k = 4) for normal maps, `colors` (k = 4) linear RGBA vertex colours.

Every generator places a unit shape with model = translate(position) . rotate(orientation) .
scale(size). `orientation` holds Euler angles in radians, applied about x, then y, then z
(R = Rz Ry Rx, right-handed). Triangles wind counter-clockwise seen from the side their normal
cross(v1 - v0, v2 - v0) points to, which is the outside of boxes and spheres.
"""

from __future__ import annotations

import numpy as np

from .errors import SceneError
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


def _finite_triangles(values: np.ndarray) -> np.ndarray:
    """Which triangles of (n, 3, k) corner values are all finite."""
    return np.isfinite(values).all(axis=(1, 2))


def _refuse_bad_triangles(shape_name: str, good: np.ndarray, values: np.ndarray, problem: str, note: str = "") -> None:
    """SceneError naming the first triangle that `good` (n bools) refuses, `problem` worded with its
    {index} and {values}, and how many there are; nothing where every triangle is good."""
    bad = np.flatnonzero(~good)
    if bad.size:
        problem = problem.format(index=int(bad[0]), values=values[bad[0]].tolist())
        raise SceneError(f"shape {shape_name!r}: {problem} ({bad.size} triangle(s) affected{note})")


def _directed_triangles(normals: np.ndarray) -> np.ndarray:
    """Which triangles' corner normals are all finite and non-zero (a zero normal has no direction)."""
    with np.errstate(all="ignore"):
        lengths = np.linalg.norm(normals, axis=-1)
    return _finite_triangles(normals) & (lengths > 0.0).all(axis=1)


def _unit_normals(normals: np.ndarray) -> np.ndarray:
    with np.errstate(all="ignore"):  # a length beyond float64's range is inf, and the normal zero
        lengths = np.linalg.norm(normals, axis=-1, keepdims=True)
    return (normals / lengths).astype(np.float32)


def _unit_interval_triangles(values: np.ndarray) -> np.ndarray:
    """Which triangles' corner values all lie in [0, 1] (NaN does not)."""
    return ((values >= 0.0) & (values <= 1.0)).all(axis=(1, 2))


def _signed_tangents(tangents: np.ndarray) -> np.ndarray:
    """Tangents with w its sign, the bitangent's handedness."""
    tangents[..., 3] = np.where(tangents[..., 3] < 0, -1.0, 1.0)
    return tangents


class CornerAttribute:
    """A per-corner attribute of Shape, declared once on the class: values (n, 3, `width`) in the
    triangles' order, or None. Assigning one checks it against the shape's triangles (SceneError
    naming the shape and the first triangle that `valid` refuses, with `problem` worded with its
    {index} and {values}; the shape stays as it was), keeps what `stored` makes of it read-only, and
    is a geometry edit (`geometry_version`). Values are read as `dtype` before the checks.
    """

    def __init__(self, width: int, problem: str, *, dtype=np.float32, valid=_finite_triangles, stored=None) -> None:
        self.width, self.problem, self.dtype, self.valid, self.stored = width, problem, dtype, valid, stored

    def __set_name__(self, owner: type, name: str) -> None:
        self.name, self.slot = name, f"_{name}"

    def __get__(self, shape: Shape | None, owner: type | None = None):
        return self if shape is None else getattr(shape, self.slot)

    def __set__(self, shape: Shape, value) -> None:
        setattr(shape, self.slot, self.checked(shape.name, value, shape.triangle_count))
        shape._edit_corners()

    def checked(self, shape_name: str, value, triangle_count: int) -> np.ndarray | None:
        """A read-only float32 copy of `value` for a shape of `triangle_count` triangles (None stays
        None), or SceneError."""
        if value is None:
            return None
        try:
            with np.errstate(over="ignore"):  # beyond dtype's range becomes inf, which `valid` refuses
                values = np.array(value, dtype=self.dtype)
        except (TypeError, ValueError) as error:
            raise SceneError(f"shape {shape_name!r}: {self.name} must be numbers, got {error}") from None
        shape = (triangle_count, 3, self.width)
        if values.shape != shape:
            raise SceneError(
                f"shape {shape_name!r}: {self.name} must have shape {shape} like the vertices, got {values.shape}"
            )
        _refuse_bad_triangles(shape_name, self.valid(values), values, self.problem)
        kept = values if self.stored is None else self.stored(values)
        kept.flags.writeable = False
        return kept


class Shape:
    """A named group of flat triangles sharing one material, placed in the world by a 4x4 transform.

    `name` names it in errors and `Scene.shape`; `tags` is a dict of anything kept with it (the
    renderer ignores it). `vertices` (n, 3, 3) float32 are local (triangle, corner, xyz); the world sees `world_vertices`,
    the transform applied in float64 (a mirroring one swaps two corners so normals keep their side;
    `world_normals`, `world_uvs` and `world_tangents` follow). Optional per-corner attributes:
    `normals` (smooth shading), `uvs` (glTF's convention, as `Texture` reads them), `tangents` (a
    file's; else MikkTSpace's) and `colors` (vertex colours, multiplying the material's colour). Assigning `vertices` or an attribute, `transform` or `material` checks
    the value (SceneError, the shape unchanged) and bumps `geometry_version`, `transform_version` or
    `material_version`, which a Renderer compares with what it uploaded: a new transform is a refit,
    new vertices a rebuild. The arrays are read-only, so an in-place edit cannot slip past them.
    """

    # unit shading normals at the corners, (n, 3, 3) float32 local, or None (flat shading)
    normals = CornerAttribute(
        3,
        "triangle {index} has a NaN, infinite or zero-length normal {values}",
        dtype=np.float64,
        valid=_directed_triangles,
        stored=_unit_normals,
    )
    # texture coordinates at the corners, (n, 3, 2) float32, or None (no textures can apply)
    uvs = CornerAttribute(2, "triangle {index} has a NaN or infinite texture coordinate {values}")
    # a file's tangents at the corners, (n, 3, 4) float32 local, or None (MikkTSpace's apply)
    tangents = CornerAttribute(4, "tangents of triangle {index} are not finite: {values}", stored=_signed_tangents)
    # linear RGBA vertex colours at the corners, (n, 3, 4) float32 in [0, 1], or None (white): they
    # multiply the material's colour and alpha (glTF's COLOR_0), as reflectances they cannot exceed 1
    colors = CornerAttribute(
        4,
        "triangle {index} has a vertex colour that is not a number in [0, 1]: {values}",
        valid=_unit_interval_triangles,
    )

    def __init__(
        self,
        name: str,
        vertices,
        material: Material,
        tags: dict | None = None,
        transform=None,
        normals=None,
        uvs=None,
        tangents=None,
        colors=None,
    ) -> None:
        self.name = name
        self.tags = dict(tags or {})
        self.geometry_version = self.transform_version = self.material_version = 0
        checked = _checked_vertices(name, vertices)
        self._normals = Shape.normals.checked(name, normals, len(checked))
        self._uvs = Shape.uvs.checked(name, uvs, len(checked))
        self._tangents = Shape.tangents.checked(name, tangents, len(checked))
        self._colors = Shape.colors.checked(name, colors, len(checked))
        self._place(checked, _IDENTITY if transform is None else checked_transform(name, transform))
        self.material = material

    def __repr__(self) -> str:
        return f"Shape({self.name!r}, {self.triangle_count} triangles, {type(self.material).__name__} {self.material.name!r})"

    @property
    def vertices(self) -> np.ndarray:
        return self._vertices

    @vertices.setter
    def vertices(self, value) -> None:
        vertices = _checked_vertices(self.name, value)
        attributes = (
            ("normals", self._normals),
            ("uvs", self._uvs),
            ("tangents", self._tangents),
            ("colors", self._colors),
        )
        for attribute, values in attributes:
            if values is not None and len(vertices) != len(values):
                raise SceneError(
                    f"shape {self.name!r}: {len(vertices)} triangles of vertices but {len(values)} of {attribute} "
                    f"(assign {attribute} = None first, or build a new Shape)"
                )
        self._place(vertices, self._transform)
        self.geometry_version += 1

    @property
    def world_uvs(self) -> np.ndarray | None:
        """The texture coordinates at the corners of `world_vertices` (a mirror swaps two corners)."""
        return _corners_following(self._uvs, self._transform)

    @property
    def world_colors(self) -> np.ndarray | None:
        """The vertex colours at the corners of `world_vertices` (a mirror swaps two corners)."""
        return _corners_following(self._colors, self._transform)

    @property
    def world_tangents(self) -> np.ndarray | None:
        """The tangents at the corners of `world_vertices`, or None."""
        if self._tangents is None or np.array_equal(self._transform, _IDENTITY):
            return self._tangents
        return transform_tangents(self._tangents, self._transform)

    @property
    def transform(self) -> np.ndarray:
        """Local to world, a 4x4 affine float64 matrix (read-only: assign a new one to move the shape)."""
        return self._transform

    @transform.setter
    def transform(self, value) -> None:
        self._place(self._vertices, checked_transform(self.name, value))
        self.transform_version += 1

    @property
    def world_vertices(self) -> np.ndarray:
        """The triangles in world coordinates, float32 (computed once per edit)."""
        return self._world

    @property
    def world_normals(self) -> np.ndarray | None:
        """The corner normals in world coordinates, unit length, float32, or None (computed once per edit)."""
        return self._world_normals

    @property
    def material(self) -> Material:
        return self._material

    @material.setter
    def material(self, value: Material) -> None:
        if not isinstance(value, Material):
            raise SceneError(f"shape {self.name!r}: material must be a Material, got {type(value).__name__}")
        self._material = value
        self.material_version += 1

    @property
    def triangle_count(self) -> int:
        return int(self._vertices.shape[0])

    def transformed(self, matrix: np.ndarray) -> Shape:
        """This shape's world triangles under an affine 4x4 or linear 3x3 matrix, baked into new
        local vertices; a mirror keeps normals facing out."""
        normals = None if self._world_normals is None else transform_normals(self._world_normals, matrix)
        uvs = _corners_following(self.world_uvs, matrix)
        colors = _corners_following(self.world_colors, matrix)
        tangents = self.world_tangents
        tangents = None if tangents is None else transform_tangents(tangents, matrix)
        world = transform_points(self._world, matrix)
        return Shape(
            self.name, world, self.material, dict(self.tags), normals=normals, uvs=uvs, tangents=tangents, colors=colors
        )

    def _edit_corners(self) -> None:
        # a CornerAttribute assigned: the world normals follow the normals
        self._place(self._vertices, self._transform)
        self.geometry_version += 1

    def _place(self, vertices: np.ndarray, transform: np.ndarray) -> None:
        # an identity stays exact: float64 arithmetic would turn -0.0 into 0.0
        world = vertices if np.array_equal(transform, _IDENTITY) else transform_points(vertices, transform)
        _refuse_bad_triangles(
            self.name,
            _finite_triangles(world),
            world,
            "the transform takes triangle {index} to non-finite coordinates {values}",
            note="; float32 ends near 3.4e38",
        )
        world.flags.writeable = False
        world_normals = self._normals
        if world_normals is not None and world is not vertices:
            world_normals = transform_normals(self._normals, transform)
            world_normals.flags.writeable = False
        self._vertices, self._transform, self._world, self._world_normals = vertices, transform, world, world_normals


_IDENTITY = np.eye(4)
_IDENTITY.flags.writeable = False


def _corners_following(values: np.ndarray | None, matrix) -> np.ndarray | None:
    """Corner values (n, 3, k) reordered as `matrix` (4x4 or 3x3) reorders the corners: a mirror
    swaps the last two, so that normals keep their side."""
    if values is None or np.linalg.det(np.asarray(matrix, np.float64)[:3, :3]) >= 0:
        return values
    return values[:, [0, 2, 1], :]


def _checked_vertices(name: str, value) -> np.ndarray:
    """A read-only (n, 3, 3) float32 copy with finite coordinates, or SceneError naming the triangle."""
    try:
        with np.errstate(over="ignore"):
            vertices = np.array(value, dtype=np.float32, order="C")
    except (TypeError, ValueError) as error:
        raise SceneError(f"shape {name!r}: vertices must be numbers, got {error}") from None
    if vertices.ndim != 3 or vertices.shape[1:] != (3, 3):
        raise SceneError(f"shape {name!r}: vertices must have shape (n, 3, 3), got {vertices.shape}")
    _refuse_bad_triangles(
        name, _finite_triangles(vertices), vertices, "triangle {index} has a NaN or infinite vertex {values}"
    )
    vertices.flags.writeable = False
    return vertices


def checked_transform(name: str, value, kind: str = "shape") -> np.ndarray:
    """A finite, invertible 4x4 affine matrix (last row 0 0 0 1) as read-only float64, or SceneError
    naming the `kind` ("shape", "instance") called `name`.

    A singular matrix would flatten every triangle to zero area; a projective last row has no
    meaning for triangles, which must stay flat.
    """
    try:
        matrix = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise SceneError(f"{kind} {name!r}: transform must be a 4x4 matrix of numbers, got {error}") from None
    if matrix.shape != (4, 4):
        raise SceneError(f"{kind} {name!r}: transform must be a 4x4 matrix, got shape {matrix.shape}")
    if not np.all(np.isfinite(matrix)):
        raise SceneError(f"{kind} {name!r}: transform has a NaN or infinite entry: {matrix.tolist()}")
    if not np.array_equal(matrix[3], [0.0, 0.0, 0.0, 1.0]):
        raise SceneError(f"{kind} {name!r}: transform must be affine (last row 0 0 0 1), got {matrix[3].tolist()}")
    with np.errstate(all="ignore"):
        determinant = np.linalg.det(matrix[:3, :3])
    if not np.isfinite(determinant) or determinant == 0.0:
        raise SceneError(
            f"{kind} {name!r}: transform has determinant {determinant}: it must be finite and non-zero "
            "(a singular matrix flattens every triangle)"
        )
    matrix.flags.writeable = False
    return matrix


def euler_rotation(orientation) -> np.ndarray:
    """R = Rz Ry Rx for Euler angles (x, y, z) in radians."""
    ax, ay, az = (float(a) for a in orientation)
    cx, sx, cy, sy, cz, sz = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay), np.cos(az), np.sin(az)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def model_matrix(position, orientation, scale) -> np.ndarray:
    """translate(position) . rotate(orientation) . scale(scale) as a 4x4 matrix: `orientation` is
    Euler angles (x, y, z) in radians applied as Rz Ry Rx, `scale` one number or three."""
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
    with np.errstate(over="ignore"):  # beyond float32's range becomes inf, which callers check
        return moved.astype(np.float32)


def transform_normals(normals: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """(n, 3, 3) unit normals under a 4x4 affine (or 3x3 linear) matrix: the inverse transpose of
    its linear part, renormalised, in float32; corners swapped as transform_points swaps them."""
    matrix = np.asarray(matrix, dtype=np.float64)
    linear = matrix[:3, :3] if matrix.shape == (4, 4) else matrix
    moved = normals.astype(np.float64) @ np.linalg.inv(linear)
    moved /= np.linalg.norm(moved, axis=-1, keepdims=True)
    if np.linalg.det(linear) < 0:
        moved = moved[:, [0, 2, 1], :]
    return moved.astype(np.float32)


def transform_tangents(tangents: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """(n, 3, 4) corner tangents under a 4x4 affine (or 3x3 linear) matrix: xyz through its linear
    part (a direction along the surface), renormalised (zero stays zero), w negated by a mirror,
    whose image turns the bitangent's handedness; corners swapped as transform_points swaps them."""
    matrix = np.asarray(matrix, dtype=np.float64)
    linear = matrix[:3, :3] if matrix.shape == (4, 4) else matrix
    xyz = tangents[..., :3].astype(np.float64) @ linear.T
    length = np.linalg.norm(xyz, axis=-1, keepdims=True)
    xyz = np.divide(xyz, length, out=np.zeros_like(xyz), where=length > 0)
    mirror = np.linalg.det(linear) < 0
    moved = np.concatenate([xyz, tangents[..., 3:] * (-1.0 if mirror else 1.0)], axis=-1)
    if mirror:
        moved = moved[:, [0, 2, 1], :]
    return moved.astype(np.float32)


def corner_normals(shapes: list[Shape], shape_index: np.ndarray, local_index: np.ndarray) -> np.ndarray | None:
    """The world corner normals (n, 3, 3) float32 of the triangles that `shape_index` and
    `local_index` pick (Scene.arrays' order: each shape's triangles together, in shape order), zero
    for those of shapes without normals (shaded flat); None where no shape has normals."""
    return _gathered([shape.world_normals for shape in shapes], shape_index, local_index)


def corner_uvs(shapes: list[Shape], shape_index: np.ndarray, local_index: np.ndarray) -> np.ndarray | None:
    """The world corner texture coordinates (n, 3, 2) float32 of the triangles that `shape_index`
    and `local_index` pick, as corner_normals picks them, zero for shapes without; None where no
    shape has any."""
    return _gathered([shape.world_uvs for shape in shapes], shape_index, local_index)


def corner_colors(shapes: list[Shape], shape_index: np.ndarray, local_index: np.ndarray) -> np.ndarray | None:
    """The world corner vertex colours (n, 3, 4) float32 of the triangles that `shape_index` and
    `local_index` pick, as corner_normals picks them, white for shapes without (a colour of 1 leaves
    the material's alone); None where no shape has any."""
    return _gathered([shape.world_colors for shape in shapes], shape_index, local_index, missing=1.0)


def _gathered(
    per_shape: list[np.ndarray | None], shape_index: np.ndarray, local_index: np.ndarray, missing: float = 0.0
) -> np.ndarray | None:
    """Each shape's world corner values (m, 3, k), or None, at the triangles that `shape_index` and
    `local_index` pick, `missing` for a shape's None; None where every shape's is."""
    present = [values for values in per_shape if values is not None]
    if not present:
        return None
    gathered = np.full((len(shape_index), 3, present[0].shape[-1]), missing, np.float32)
    starts = np.searchsorted(shape_index, np.arange(len(per_shape) + 1))
    for index, values in enumerate(per_shape):
        if values is not None:
            rows = slice(starts[index], starts[index + 1])
            gathered[rows] = values[local_index[rows]]
    return gathered


def _place(name: str, corners: np.ndarray, faces: np.ndarray, matrix: np.ndarray, material: Material) -> Shape:
    return Shape(name, transform_points(corners[faces], matrix), material)


def make_plane(position, orientation, size, material: Material, name: str = "plane") -> Shape:
    """Two triangles: a size[0] x size[1] rectangle in the local xz plane facing +y, rotated by
    `orientation` (Euler angles in radians, as `model_matrix`) and centred at `position`; a Shape
    called `name` of `material`."""
    width, depth = (float(s) for s in size)
    return _place(
        name, _PLANE_CORNERS, _PLANE_FACES, model_matrix(position, orientation, (width, 1.0, depth)), material
    )


def make_box(position, orientation, size, material: Material, name: str = "box") -> Shape:
    """Twelve triangles: a box of edge lengths `size` (x, y, z) centred at `position`, rotated by
    `orientation` (Euler angles in radians, as `model_matrix`); a Shape called `name` of `material`."""
    return _place(name, _BOX_CORNERS, _BOX_FACES, model_matrix(position, orientation, size), material)


def make_icosphere(
    position,
    orientation,
    radius: float,
    iterations: int,
    material: Material,
    name: str = "icosphere",
    smooth: bool = False,
) -> Shape:
    """An icosahedron subdivided `iterations` times (20 * 4**iterations triangles), radius `radius`,
    centred at `position` and turned by `orientation` (Euler angles in radians, as `model_matrix`): a
    Shape called `name` of `material`. `smooth` gives it the sphere's normals at the corners (smooth
    shading), else it shades flat. ValueError for negative `iterations`.

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
    # a corner of the unit sphere is its own normal
    normals = transform_normals(triangles, matrix) if smooth else None
    return Shape(name, transform_points(triangles, matrix), material, normals=normals)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)
