"""A Shape's corner normals: checked, stored unit length, carried through transforms (inverse
transpose, mirrors swap corners with the vertices) and counted as geometry edits."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.scene import Diffuse, SceneError, Shape
from wgputrace.scene.shapes import make_icosphere, model_matrix

GREY = Diffuse("grey", color=(0.5, 0.5, 0.5))
TRIANGLE = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]


def test_normals_are_normalised_and_transformed_by_the_inverse_transpose():
    shape = Shape("t", TRIANGLE, GREY, normals=[[[0, 0, 2], [1, 0, 1], [0, 1, 1]]])
    np.testing.assert_allclose(np.linalg.norm(shape.normals, axis=-1), 1.0, rtol=1e-6)
    shape.transform = np.diag([4.0, 1.0, 1.0, 1.0])
    expected = np.array([[0, 0, 1], [0.25, 0, 1], [0, 1, 1]])
    np.testing.assert_allclose(shape.world_normals[0], expected / np.linalg.norm(expected, axis=1)[:, None], rtol=1e-6)


def test_a_mirror_swaps_normals_with_their_corners():
    shape = Shape("t", TRIANGLE, GREY, normals=[[[0, 0, 1], [1, 0, 1], [0, 1, 1]]])
    shape.transform = np.diag([-1.0, 1.0, 1.0, 1.0])
    # corners 1 and 2 swap; the normal of corner (1, 0, 0), now (-1, 0, 0), goes with it
    np.testing.assert_array_equal(shape.world_vertices[0, 2], [-1, 0, 0])
    np.testing.assert_allclose(shape.world_normals[0, 2], np.array([-1, 0, 1]) / np.sqrt(2), rtol=1e-6)


@pytest.mark.parametrize("bad", [[0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 1]])
def test_a_normal_without_direction_is_a_scene_error_naming_shape_and_triangle(bad):
    with pytest.raises(SceneError, match=r"shape 'tri': triangle 0 has a NaN, infinite or zero-length normal"):
        Shape("tri", TRIANGLE, GREY, normals=[[[0, 0, 1], bad, [0, 0, 1]]])


def test_normal_edits_are_checked_and_counted():
    shape = Shape("t", TRIANGLE, GREY)
    assert shape.normals is None and shape.world_normals is None
    with pytest.raises(SceneError, match=r"normals must have shape \(1, 3, 3\)"):
        shape.normals = [[0, 0, 1]]
    assert shape.geometry_version == 0
    shape.normals = [[[0, 0, 1]] * 3]
    assert shape.geometry_version == 1
    with pytest.raises(SceneError, match="2 triangles of vertices but 1 of normals"):
        shape.vertices = TRIANGLE * 2
    shape.normals = None
    shape.vertices = TRIANGLE * 2
    assert shape.geometry_version == 3 and shape.normals is None


def test_smooth_icosphere_normals_are_the_sphere_normals():
    sphere = make_icosphere((1, 2, 3), (0.3, 0.2, 0.1), 2.0, 1, GREY, smooth=True)
    radial = sphere.world_vertices - np.array([1, 2, 3], np.float32)
    np.testing.assert_allclose(sphere.world_normals, radial / 2.0, atol=1e-5)
    moved = sphere.transformed(model_matrix((0, 0, 0), (0, 0, 0), (1, 1, -1)))
    np.testing.assert_allclose(np.linalg.norm(moved.world_normals, axis=-1), 1.0, rtol=1e-6)
