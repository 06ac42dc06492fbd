"""Tangents for normal maps where a file gives none: MikkTSpace's essentials in numpy, as the glTF
spec asks ("client implementations SHOULD calculate tangents using default MikkTSpace algorithms").
No maintained MikkTSpace package has wheels for current Pythons, so `mikktspace_tangents`
implements the steps of Mikkelsen's mikktspace.c that decide the result for the meshes we load.
"""

from __future__ import annotations

import numpy as np

# Below this a UV area, a projected direction or a normal has no reliable direction in float64
# (mikktspace.c's NotZero threshold is float32's smallest normal; ours also covers rounding).
DEGENERATE = 1e-20


def mikktspace_tangents(vertices, uvs, normals=None) -> np.ndarray:
    """Corner tangents (n, 3, 4) float32 of triangles `vertices` (n, 3, 3) with corner texture
    coordinates `uvs` (n, 3, 2, glTF's convention) and corner `normals` (n, 3, 3; None or a zero
    corner: the face's normal): xyz unit and perpendicular to the normal, w = +1 or -1.

    Per triangle, dP/du from the UV derivatives and whether the UV map keeps its orientation (w); per
    corner, that direction projected into the plane of the corner's normal, weighted by the corner's
    angle there; summed over the corners sharing a vertex (position, normal, uv) and orientation, then
    projected and normalised again. Unlike mikktspace.c, a vertex whose fan is not connected is merged,
    not split. UV-degenerate triangles add nothing; a vertex given nothing gets any perpendicular.
    """
    vertices = np.asarray(vertices, np.float64)
    # glTF's v points down the image and a tangent-space normal's +Y up it: (u, 1 - v), as Blender
    # computes the TANGENTs it exports (bitangent = cross(normal, tangent) * w points up the image)
    uvs = np.asarray(uvs, np.float64) * (1.0, -1.0) + (0.0, 1.0)
    normals = _corner_normals(vertices, normals)
    direction, preserving = _triangle_directions(vertices, uvs)
    weights = _corner_angles(vertices, normals)
    contribution = _projected(np.broadcast_to(direction[:, None, :], normals.shape), normals) * weights[..., None]
    sums = _shared_vertex_sums(vertices, normals, uvs, preserving, contribution)
    tangents = _projected(sums, normals)
    missing = ~(np.linalg.norm(tangents, axis=-1) > 0.5)
    tangents[missing] = _any_perpendicular(normals[missing])
    w = np.where(preserving, 1.0, -1.0)
    return np.concatenate([tangents, np.broadcast_to(w[:, None, None], (*tangents.shape[:2], 1))], axis=-1).astype(
        np.float32
    )


def corner_tangents(shapes: list, shape_index: np.ndarray, local_index: np.ndarray) -> np.ndarray:
    """The world corner tangents (n, 3, 4) float32 of the triangles that `shape_index` and
    `local_index` pick (`corner_uvs`' order): a shape's own (a file's TANGENT), else
    MikkTSpace's computed in world space (it commutes with rotation and scale; a mirror's swapped
    corners keep the bitangent up the image); zero for shapes with neither tangents nor texture
    coordinates."""
    tangents = np.zeros((len(shape_index), 3, 4), np.float32)
    starts = np.searchsorted(shape_index, np.arange(len(shapes) + 1))
    for index, shape in enumerate(shapes):
        world = shape.world_tangents
        if world is None and shape.uvs is not None:
            world = mikktspace_tangents(shape.world_vertices, shape.world_uvs, shape.world_normals)
        if world is not None:
            rows = slice(starts[index], starts[index + 1])
            tangents[rows] = world[local_index[rows]]
    return tangents


def _unit_or_zero(v: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, length, out=np.zeros_like(v), where=length > DEGENERATE)


def _corner_normals(vertices: np.ndarray, normals) -> np.ndarray:
    """Unit corner normals; the face normal where a corner has none (or a zero one)."""
    face = _unit_or_zero(np.cross(vertices[:, 1] - vertices[:, 0], vertices[:, 2] - vertices[:, 0]))
    given = np.zeros_like(vertices) if normals is None else _unit_or_zero(np.asarray(normals, np.float64))
    missing = ~np.isfinite(given).all(axis=-1) | (np.linalg.norm(given, axis=-1) < 0.5)
    return np.where(missing[..., None], face[:, None, :], given)


def _triangle_directions(vertices: np.ndarray, uvs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each triangle's unit dP/du (zero where its texture coordinates have no area) and whether its
    UV map keeps its orientation (mikktspace.c's vOs and ORIENT_PRESERVING)."""
    d1, d2 = vertices[:, 1] - vertices[:, 0], vertices[:, 2] - vertices[:, 0]
    t1, t2 = uvs[:, 1] - uvs[:, 0], uvs[:, 2] - uvs[:, 0]
    signed_area = t1[:, 0] * t2[:, 1] - t1[:, 1] * t2[:, 0]
    preserving = signed_area > 0
    sign = np.where(preserving, 1.0, -1.0)[:, None]
    direction = sign * _unit_or_zero(t2[:, 1:2] * d1 - t1[:, 1:2] * d2)
    return np.where((np.abs(signed_area) > DEGENERATE)[:, None], direction, 0.0), preserving


def _corner_angles(vertices: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Each corner's angle between its two edges, both projected into the plane of its normal."""
    following = _projected(np.roll(vertices, -1, axis=1) - vertices, normals)
    preceding = _projected(np.roll(vertices, 1, axis=1) - vertices, normals)
    return np.arccos(np.clip(np.einsum("nkd,nkd->nk", following, preceding), -1.0, 1.0))


def _projected(v: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """`v` without its component along `normals`, unit length (zero where nothing is left)."""
    return _unit_or_zero(v - normals * np.einsum("nkd,nkd->nk", v, normals)[..., None])


def _shared_vertex_sums(vertices, normals, uvs, preserving, contribution) -> np.ndarray:
    """Each corner's sum of the contributions of every corner with its position, normal, texture
    coordinates and orientation (one vertex of an indexed mesh, as mikktspace.c groups them)."""
    keys = np.concatenate(
        [vertices, normals, uvs, np.broadcast_to(preserving[:, None, None], (*vertices.shape[:2], 1))], axis=-1
    ).reshape(-1, 9)
    _, group = np.unique(keys, axis=0, return_inverse=True)
    group = group.reshape(-1)
    sums = np.zeros((group.max(initial=-1) + 1, 3))
    np.add.at(sums, group, contribution.reshape(-1, 3))
    return sums[group].reshape(contribution.shape)


def _any_perpendicular(normals: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each unit normal (Duff et al. 2017's branchless basis)."""
    sign = np.where(normals[:, 2] >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + normals[:, 2])
    b = normals[:, 0] * normals[:, 1] * a
    return np.stack([1.0 + sign * normals[:, 0] ** 2 * a, sign * b, -sign * normals[:, 0]], axis=-1)
