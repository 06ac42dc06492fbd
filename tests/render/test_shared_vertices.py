"""Shading attributes per vertex (`shared_vertices`): the corners come back bit for bit, a mesh's
index buffer comes back as its vertices, a move keeps the indices, and a smooth textured mesh's GPU
records are the bytes its vertices and triangles account for, within twice the flat Cornell box's."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Renderer, make_box, model_matrix
from wgputrace.gpu.layout import TRIANGLE_VERTICES, VERTEX_NORMAL, VERTEX_TANGENT, VERTEX_UV
from wgputrace.render import shared_vertices as shared_vertices_module
from wgputrace.render.scene_mirror import (
    TEXTURE_ATLAS,
    VERTEX_ARRAYS,
    VERTEX_INDICES,
    VERTEX_NORMALS,
    VERTEX_TANGENTS,
    VERTEX_UVS,
    SceneMirror,
)
from wgputrace.render.shared_vertices import corner_values, shared_vertices, triangle_vertex_records, vertex_records
from wgputrace.scene import cornell_box
from wgputrace.testing.uv_sphere import textured_sphere, uv_sphere

SEGMENTS = 12  # 528 triangles over 12 rings
TRIANGLES = 4 * SEGMENTS**2 - 4 * SEGMENTS
# issue 25: a smooth, textured mesh at most this many times the flat Cornell box's bytes per triangle
FLAT_RATIO_TARGET = 2.0


def test_corners_come_back_bit_for_bit_and_equal_ones_share_a_vertex(rng):
    pool = rng.normal(size=(5, 3)).astype(np.float32)
    pool[0] = (0.0, 0.0, 0.0)
    pool[1] = (-0.0, 0.0, 0.0)  # another vertex than +0: the GPU must read the bits it was given
    normals = pool[rng.integers(0, len(pool), (40, 3))]
    uvs = rng.integers(0, 2, (40, 3, 2)).astype(np.float32)
    indices, vertices = shared_vertices({VERTEX_NORMALS: normals, VERTEX_UVS: uvs})
    records = triangle_vertex_records(indices)
    for name, corners in ((VERTEX_NORMALS, normals), (VERTEX_UVS, uvs)):
        back = corner_values(records, vertex_records(VERTEX_ARRAYS[name], vertices[name]))
        np.testing.assert_array_equal(back.view(np.uint32), corners.view(np.uint32))
    distinct = np.unique(np.concatenate([normals, uvs], axis=-1).reshape(-1, 5).view(np.uint32), axis=0)
    assert len(vertices[VERTEX_NORMALS]) == len(distinct) < 3 * len(normals)
    # numbered by first appearance: the first corner is vertex 0, each new one the next number
    first_seen = np.maximum.accumulate(indices.reshape(-1))
    assert indices[0, 0] == 0 and (np.diff(first_seen) <= 1).all()


def test_rows_sharing_a_hash_are_told_apart(rng, monkeypatch):
    """Were every corner's hash the same, the corners themselves decide which are one vertex."""
    normals = rng.normal(size=(30, 3, 3)).astype(np.float32)
    normals[:, 2] = normals[:, 0]
    monkeypatch.setattr(shared_vertices_module, "_row_hashes", lambda words: np.zeros(len(words), np.uint64))
    indices, vertices = shared_vertices({VERTEX_NORMALS: normals})
    assert len(vertices[VERTEX_NORMALS]) == 60 and (indices[:, 0] == indices[:, 2]).all()
    np.testing.assert_array_equal(vertices[VERTEX_NORMALS][indices], normals)


def test_no_triangles_no_vertices():
    indices, vertices = shared_vertices({VERTEX_NORMALS: np.zeros((0, 3, 3), np.float32)})
    assert indices.shape == (0, 3) and vertices[VERTEX_NORMALS].shape == (0, 3)


def test_a_meshs_index_buffer_comes_back_as_its_vertices():
    """The mirror finds the vertices the index buffer shared (those its triangles use), no more."""
    _, _, _, triangles = uv_sphere(SEGMENTS)
    mirror = SceneMirror(textured_sphere(SEGMENTS), "bvh")
    assert len(mirror.triangles) == TRIANGLES
    vertex_count = len(np.unique(triangles))
    for name in (VERTEX_NORMALS, VERTEX_UVS, VERTEX_TANGENTS):
        assert len(mirror.vertices[name]) == vertex_count, name


@pytest.mark.gpu
def test_a_smooth_textured_mesh_costs_what_its_records_count_within_twice_the_flat_box():
    sphere = Renderer(textured_sphere(SEGMENTS), 8, 8)
    vertex_count = len(np.unique(uv_sphere(SEGMENTS)[3]))
    buffers = sphere.gpu_scene_bytes
    assert buffers[VERTEX_INDICES] == TRIANGLES * TRIANGLE_VERTICES.size == TRIANGLES * 12
    assert buffers[VERTEX_NORMALS] == vertex_count * VERTEX_NORMAL.size == vertex_count * 12
    assert buffers[VERTEX_UVS] == vertex_count * VERTEX_UV.size == vertex_count * 8
    assert buffers[VERTEX_TANGENTS] == vertex_count * VERTEX_TANGENT.size == vertex_count * 16
    assert TEXTURE_ATLAS in buffers  # textured, and left out of the bytes per triangle
    flat = Renderer(cornell_box(), 8, 8)
    assert sphere.gpu_bytes_per_triangle <= FLAT_RATIO_TARGET * flat.gpu_bytes_per_triangle


@pytest.mark.gpu
def test_moving_a_smooth_textured_mesh_uploads_its_vertices_not_its_indices():
    scene = textured_sphere(SEGMENTS)
    renderer = Renderer(scene, 8, 8)
    # a small turn: a refit (a larger one would make the tree slow enough to rebuild)
    scene.shapes[0].transform = model_matrix((0.0, 0.0, 0.0), (0.0, 0.05, 0.02), 1.0)
    uploads = renderer.update()
    assert renderer._mirror.refits == 1
    assert {VERTEX_NORMALS, VERTEX_TANGENTS} <= set(uploads) and VERTEX_INDICES not in uploads
    assert VERTEX_UVS not in uploads  # a turn moves no texture coordinate
    # each triangle's corners (in the scene's order: a fresh build orders the triangles its own way)
    # read what a fresh mirror of the moved scene gives them
    edited, fresh = renderer._mirror, SceneMirror(scene, "bvh")
    for name in (VERTEX_NORMALS, VERTEX_UVS, VERTEX_TANGENTS):
        corners = (
            corner_values(mirror.vertices[VERTEX_INDICES], mirror.vertices[name])[mirror._position]
            for mirror in (edited, fresh)
        )
        np.testing.assert_array_equal(*corners, err_msg=name)
    # the normal map removed: one zero tangent, the others kept
    scene.shapes[0].material.normal_texture = None
    renderer.update()
    assert len(renderer._mirror.vertices[VERTEX_TANGENTS]) == 1 and VERTEX_NORMALS in renderer._mirror.vertices


def test_moving_a_shape_without_attributes_beside_a_smooth_one_leaves_the_vertices():
    scene = textured_sphere(SEGMENTS)
    scene.shapes[0].material.normal_texture = None  # tangents follow every position under a map
    scene.add(make_box((2, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("box"), "box"))
    mirror = SceneMirror(scene, "bvh")
    before = dict(mirror.vertices)
    scene.shape("box").transform = model_matrix((0.0, 0.1, 0.0), (0.0, 0.0, 0.0), 1.0)
    changes = mirror.update()
    assert mirror.refits == 1 and not set(changes) & {VERTEX_INDICES, *VERTEX_ARRAYS}
    assert all(mirror.vertices[name] is records for name, records in before.items())
