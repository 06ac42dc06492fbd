"""Shape generators: counts, placement, orientation conventions, outward normals, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Diffuse, make_box, make_icosphere, make_plane
from wgputrace.scene.shapes import Shape, euler_rotation

WHITE = Diffuse("white")


def normals(shape: Shape) -> np.ndarray:
    v = shape.vertices.astype(np.float64)
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


@pytest.mark.parametrize("iterations", [0, 1, 2, 3])
def test_icosphere_counts_radius_and_outward_normals(iterations):
    center = np.array([0.3, -1.0, 2.0])
    sphere = make_icosphere(center, (0.1, 0.2, 0.3), 0.5, iterations, WHITE)
    assert sphere.triangle_count == 20 * 4**iterations
    radii = np.linalg.norm(sphere.vertices.reshape(-1, 3) - center, axis=1)
    np.testing.assert_allclose(radii, 0.5, rtol=1e-6)
    outward = sphere.vertices.mean(axis=1) - center
    assert np.all(np.sum(normals(sphere) * outward, axis=1) > 0)


def test_box_is_closed_with_outward_normals_and_right_extent():
    box = make_box((1, 2, 3), (0, 0, 0), (2, 4, 6), WHITE)
    assert box.triangle_count == 12
    flat = box.vertices.reshape(-1, 3)
    np.testing.assert_allclose(flat.min(axis=0), [0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(flat.max(axis=0), [2, 4, 6], atol=1e-6)
    outward = box.vertices.mean(axis=1) - [1, 2, 3]
    assert np.all(np.sum(normals(box) * outward, axis=1) > 0)
    # closed: every edge is used exactly twice, once in each direction
    edges = {}
    for tri in np.round(box.vertices, 5).tolist():
        for a, b in ((0, 1), (1, 2), (2, 0)):
            key = (tuple(tri[a]), tuple(tri[b]))
            edges[key] = edges.get(key, 0) + 1
    assert all(count == 1 and edges.get((b, a)) == 1 for (a, b), count in edges.items())


def test_plane_size_orientation_and_normal():
    plane = make_plane((0, 0, 0), (0, 0, 0), (2, 3), WHITE)
    assert plane.triangle_count == 2
    np.testing.assert_allclose(normals(plane), [[0, 1, 0], [0, 1, 0]], atol=1e-7)
    flat = plane.vertices.reshape(-1, 3)
    np.testing.assert_allclose(flat.max(axis=0) - flat.min(axis=0), [2, 0, 3], atol=1e-7)
    # rotating by -pi/2 about z turns +y into +x (right-handed)
    turned = make_plane((0, 0, 0), (0, 0, -math.pi / 2), (1, 1), WHITE)
    np.testing.assert_allclose(normals(turned), [[1, 0, 0], [1, 0, 0]], atol=1e-6)


def test_euler_order_is_x_then_y_then_z():
    angles = (0.3, -0.7, 1.1)
    rx = euler_rotation((angles[0], 0, 0))
    ry = euler_rotation((0, angles[1], 0))
    rz = euler_rotation((0, 0, angles[2]))
    np.testing.assert_allclose(euler_rotation(angles), rz @ ry @ rx, atol=1e-12)
    assert np.linalg.det(euler_rotation(angles)) == pytest.approx(1.0)


def test_mirror_keeps_normals_outward():
    sphere = make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 1, WHITE)
    mirrored = sphere.transformed(np.diag([-1.0, 1.0, 1.0]))
    outward = mirrored.vertices.mean(axis=1)
    assert np.all(np.sum(normals(mirrored) * outward, axis=1) > 0)


def test_bad_vertices_name_the_triangle():
    vertices = np.zeros((4, 3, 3), np.float32)
    vertices[2, 1, 0] = np.nan
    with pytest.raises(ValueError, match="triangle 2"):
        Shape("broken", vertices, WHITE)
    with pytest.raises(ValueError, match=r"\(n, 3, 3\)"):
        Shape("flat", np.zeros((4, 9), np.float32), WHITE)
    with pytest.raises(ValueError, match="iterations"):
        make_icosphere((0, 0, 0), (0, 0, 0), 1.0, -1, WHITE)
