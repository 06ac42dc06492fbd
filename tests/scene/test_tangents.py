"""mikktspace_tangents and corner_tangents against hand-computed tangents: dP/du of a plain, a stretched, a sheared and a
mirrored UV map (w the bitangent's sign, up the image as glTF's normal maps mean it), the angle
weighting where triangles share a vertex, and a valid tangent, never NaN, where texture coordinates
or normals are degenerate. Shape(tangents=): checked, mirrored with the shape, preferred over
MikkTSpace's; glTF's TANGENT is read and agrees with what MikkTSpace computes for the same square."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from wgputrace import load_scene
from wgputrace.scene import Principled, SceneError, Shape
from wgputrace.scene.tangents import corner_tangents, mikktspace_tangents
from wgputrace.testing.gltf_files import SQUARE_INDICES, SQUARE_TANGENTS, textured_square, write_glb

# one triangle in the xy plane facing +z; the image's top (v = 0) at y = 1
TRIANGLE = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
UP = np.array([[[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]])


def bitangent(tangents: np.ndarray, normal=(0.0, 0.0, 1.0)) -> np.ndarray:
    """glTF's bitangent: cross(normal, tangent.xyz) * w."""
    return np.cross(normal, tangents[..., :3]) * tangents[..., 3:]


@pytest.mark.parametrize(
    ("uvs", "tangent", "w"),
    [
        (UP, (1.0, 0.0, 0.0), 1.0),
        # u runs twice as fast: dP/du is shorter, its direction the same
        (UP * (2.0, 1.0), (1.0, 0.0, 0.0), 1.0),
        # sheared: u = x and v' = 1 - v = x + y, so P(u, v') = (u, v' - u) and dP/du = (1, -1, 0)
        (np.array([[[0.0, 1.0], [1.0, 0.0], [0.0, 0.0]]]), (1.0, -1.0, 0.0), 1.0),
        # mirrored in u: the tangent turns round, the bitangent stays up the image
        (UP * (-1.0, 1.0), (-1.0, 0.0, 0.0), -1.0),
    ],
)
def test_one_triangle_gets_dp_du_and_the_bitangent_up_the_image(uvs, tangent, w):
    tangents = mikktspace_tangents(TRIANGLE, uvs)
    assert tangents.shape == (1, 3, 4) and tangents.dtype == np.float32
    expected = np.array(tangent) / np.linalg.norm(tangent)
    np.testing.assert_allclose(tangents[..., :3], np.broadcast_to(expected, (1, 3, 3)), atol=1e-6)
    np.testing.assert_array_equal(tangents[..., 3], w)


def test_the_bitangent_points_up_the_image():
    """v' = 1 - v grows with y, so a normal map's +Y (up the image) is +y."""
    np.testing.assert_allclose(bitangent(mikktspace_tangents(TRIANGLE, UP))[0], [[0.0, 1.0, 0.0]] * 3, atol=1e-6)


def test_a_shared_vertex_averages_its_triangles_by_corner_angle():
    """Two triangles meet at the origin with the same normal (+z) and texture coordinates there, at
    corner angles 90 and 45 degrees, their dP/du along x and along y: the shared corner's tangent is
    their sum weighted pi/2 : pi/4, the unshared corners keep their triangle's own."""
    a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    b = [[0.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    # b's u grows with y: u = y, v' = -x
    uvs = np.array([[[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]], [[0.0, 1.0], [1.0, 0.0], [0.0, 0.0]]])
    tangents = mikktspace_tangents(np.array([a, b]), uvs, normals=np.broadcast_to([0.0, 0.0, 1.0], (2, 3, 3)))
    shared = np.array([np.pi / 2, np.pi / 4, 0.0]) / np.hypot(np.pi / 2, np.pi / 4)
    np.testing.assert_allclose(tangents[0, 0, :3], shared, atol=1e-6)
    np.testing.assert_allclose(tangents[1, 0, :3], shared, atol=1e-6)
    np.testing.assert_allclose(tangents[0, 1, :3], [1.0, 0.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(tangents[1, 1, :3], [0.0, 1.0, 0.0], atol=1e-6)


def test_tangents_are_perpendicular_to_the_corner_normals():
    rng = np.random.default_rng(20_261_201)
    vertices, uvs = rng.normal(size=(200, 3, 3)), rng.random((200, 3, 2))
    normals = rng.normal(size=(200, 3, 3))
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    tangents = mikktspace_tangents(vertices, uvs, normals)
    np.testing.assert_allclose(np.linalg.norm(tangents[..., :3], axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.einsum("nkd,nkd->nk", tangents[..., :3], normals), 0.0, atol=1e-5)


@pytest.mark.parametrize(
    ("vertices", "uvs", "normals"),
    [
        # every texture coordinate the same
        (TRIANGLE, np.full((1, 3, 2), 0.25), None),
        # texture coordinates on a line
        (TRIANGLE, np.array([[[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]]]), None),
        # zero corner normals and a zero-area triangle
        (np.zeros((1, 3, 3)), UP, np.zeros((1, 3, 3))),
        # normals along dP/du: nothing of it is left in their plane
        (TRIANGLE, UP, np.broadcast_to([1.0, 0.0, 0.0], (1, 3, 3))),
    ],
)
def test_degenerate_input_gives_a_valid_tangent_never_nan(vertices, uvs, normals):
    tangents = mikktspace_tangents(vertices, uvs, normals)
    assert np.isfinite(tangents).all()
    np.testing.assert_allclose(np.linalg.norm(tangents[..., :3], axis=-1), 1.0, atol=1e-6)
    assert set(np.unique(tangents[..., 3])) <= {-1.0, 1.0}
    if normals is not None and np.any(normals):
        np.testing.assert_allclose(np.einsum("nkd,nkd->nk", tangents[..., :3], normals), 0.0, atol=1e-6)


def test_shape_tangents_are_checked_and_w_kept_as_its_sign():
    shape = Shape("t", TRIANGLE, Principled("p"), tangents=[[[1.0, 0.0, 0.0, 0.5]] * 3])
    np.testing.assert_array_equal(shape.tangents[..., 3], 1.0)
    with pytest.raises(SceneError, match=r"shape 't': tangents must have shape \(1, 3, 4\)"):
        Shape("t", TRIANGLE, Principled("p"), tangents=np.zeros((1, 3, 3)))
    with pytest.raises(SceneError, match=r"shape 't': tangents of triangle 0 are not finite"):
        Shape("t", TRIANGLE, Principled("p"), tangents=[[[np.nan, 0.0, 0.0, 1.0]] * 3])


def test_a_mirror_turns_the_tangents_and_their_handedness_with_the_corners():
    """Mirrored in x, corners 1 and 2 swap (transform_points keeps the winding) and the image's
    mirror makes the bitangent's handedness flip: what MikkTSpace computes on the mirrored shape."""
    tangents = np.array([[[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, -1.0]]])
    shape = Shape("t", TRIANGLE, Principled("p"), uvs=UP, tangents=tangents)
    shape.transform = np.diag([-2.0, 1.0, 1.0, 1.0])
    expected = [[[-1.0, 0.0, 0.0, -1.0], [0.0, 0.0, 1.0, 1.0], [0.0, 1.0, 0.0, -1.0]]]
    np.testing.assert_allclose(shape.world_tangents, expected, atol=1e-6)
    np.testing.assert_allclose(shape.transformed(np.eye(4)).tangents, expected, atol=1e-6)
    mikk = mikktspace_tangents(shape.world_vertices, shape.world_uvs)
    np.testing.assert_allclose(mikk, [[[-1.0, 0.0, 0.0, -1.0]] * 3], atol=1e-6)


def test_scene_tangents_prefer_the_shape_s_own():
    given = np.array([[[0.0, 1.0, 0.0, -1.0]] * 3])
    own = Shape("own", TRIANGLE, Principled("p"), uvs=UP, tangents=given)
    computed = Shape("computed", TRIANGLE, Principled("p"), uvs=UP)
    bare = Shape("bare", TRIANGLE, Principled("p"))
    tangents = corner_tangents([own, computed, bare], np.array([0, 1, 2]), np.array([0, 0, 0]))
    np.testing.assert_array_equal(tangents[0], given[0])
    np.testing.assert_allclose(tangents[1], [[1.0, 0.0, 0.0, 1.0]] * 3, atol=1e-6)
    np.testing.assert_array_equal(tangents[2], 0.0)


def test_gltf_tangent_is_read_and_agrees_with_mikktspace(tmp_path):
    document, blob = textured_square()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the material's parameters Principled lacks so far
        (shape,) = load_scene(write_glb(tmp_path / "square.glb", document, blob)).shapes
    np.testing.assert_array_equal(shape.tangents, SQUARE_TANGENTS[SQUARE_INDICES])
    np.testing.assert_allclose(mikktspace_tangents(shape.vertices, shape.uvs, shape.normals), shape.tangents, atol=1e-6)
