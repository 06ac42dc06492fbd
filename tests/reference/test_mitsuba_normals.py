"""Per-vertex normals reach Mitsuba as its vertex normals (face_normals off), the triangles of a
flat shape in the same mesh as their face normal at each corner. Needs mitsuba (the `reference`
extra), which CI does not install."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.reference.mitsuba_scene import SCALAR_VARIANT, load_mitsuba, mitsuba_scene
from wgputrace.scene import Camera, Diffuse, Scene
from wgputrace.scene.shapes import make_icosphere, make_plane

pytest.importorskip("mitsuba", reason="Mitsuba 3 (the reference extra) is not installed")

GREY = Diffuse("grey", color=(0.5, 0.5, 0.5))


def test_vertex_normals_and_flat_corners():
    mi = load_mitsuba(SCALAR_VARIANT)
    ball = make_icosphere((0, 1, 0), (0, 0, 0), 0.5, 1, GREY, "ball", smooth=True)
    floor = make_plane((0, 0, 0), (0, 0, 0), (4, 4), GREY, "floor")
    theirs = mitsuba_scene(mi, Scene([ball, floor], Camera()), 8, 8, 3)
    (mesh,) = theirs.shapes()
    assert mesh.has_vertex_normals()
    params = mi.traverse(mesh)
    normals = np.array(params["vertex_normals"]).reshape(-1, 3, 3)
    np.testing.assert_allclose(normals[: ball.triangle_count], ball.world_normals, atol=1e-6)
    np.testing.assert_allclose(normals[ball.triangle_count :], [[[0, 1, 0]] * 3] * 2, atol=1e-6)
    # Mitsuba shades with them: the normal it reports at a point is the interpolated one
    ray = mi.Ray3f(mi.Point3f(0.1, 3.0, 0.05), mi.Vector3f(0, -1, 0))
    hit = theirs.ray_intersect(ray)
    radial = np.array(hit.p) - [0, 1, 0]
    assert np.dot(np.array(hit.sh_frame.n), radial / np.linalg.norm(radial)) > 0.999
    assert np.dot(np.array(hit.sh_frame.n), np.array(hit.n)) < 0.99999
