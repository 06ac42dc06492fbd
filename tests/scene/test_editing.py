"""The Scene editing API: every edit is checked where it happens, bumps the version a Renderer
watches, and a rejected edit leaves the scene as it was."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Glass, Glossy, Scene, Shape, make_box, model_matrix
from wgputrace.scene import MaterialError, SceneError


@pytest.fixture
def box() -> Shape:
    return make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("white"), "box")


def test_transform_moves_world_vertices_and_only_bumps_its_version(box):
    local = box.vertices.copy()
    versions = (box.geometry_version, box.transform_version, box.material_version)
    box.transform = model_matrix((1, 2, 3), (0, 0, 0), 2.0)
    np.testing.assert_array_equal(box.vertices, local)  # local vertices stay as made
    np.testing.assert_allclose(box.world_vertices, local * 2 + [1, 2, 3], rtol=1e-6)
    assert (box.geometry_version, box.transform_version, box.material_version) == (
        versions[0],
        versions[1] + 1,
        versions[2],
    )


def test_mirroring_transform_keeps_normals_outwards(box):
    box.transform = np.diag([-1.0, 1.0, 1.0, 1.0])
    v = box.world_vertices.astype(np.float64)
    normals = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    assert np.all(np.sum(normals * v.mean(axis=1), axis=1) > 0)


@pytest.mark.parametrize(
    "matrix, message",
    [
        (np.full((4, 4), np.nan), "NaN or infinite entry"),
        (np.eye(3), r"4x4 matrix, got shape \(3, 3\)"),
        (np.diag([1.0, 0.0, 1.0, 1.0]), "determinant 0.0"),
        (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]), "affine"),
        (np.diag([1e39, 1.0, 1.0, 1.0]), "non-finite coordinates"),
        ("spin", "matrix of numbers"),
    ],
)
def test_bad_transforms_are_named_and_change_nothing(box, matrix, message):
    before = (box.transform.copy(), box.world_vertices.copy(), box.transform_version)
    with pytest.raises(SceneError, match=message):
        box.transform = matrix
    np.testing.assert_array_equal(box.transform, before[0])
    np.testing.assert_array_equal(box.world_vertices, before[1])
    assert box.transform_version == before[2]


def test_arrays_cannot_be_edited_in_place_behind_the_versions(box):
    with pytest.raises(ValueError, match="read-only"):
        box.vertices[0, 0, 0] = 5.0
    with pytest.raises(ValueError, match="read-only"):
        box.transform[0, 3] = 5.0


def test_new_vertices_are_checked_and_bump_the_geometry_version(box):
    version = box.geometry_version
    bad = np.array(box.vertices)
    bad[7, 2, 1] = np.inf
    with pytest.raises(SceneError, match="triangle 7 has a NaN or infinite vertex"):
        box.vertices = bad
    assert box.geometry_version == version and box.triangle_count == 12
    box.vertices = box.vertices[:6]
    assert box.geometry_version == version + 1 and box.triangle_count == 6


def test_material_edits_are_checked_restored_on_error_and_versioned():
    glass = Glass("glass", color=(0.9, 0.9, 0.9), ior=1.5)
    glass.ior = 1.33
    assert glass.ior == 1.33 and glass.version == 1
    for parameter, value, message in (
        ("ior", 0.0, r"ior must be in \(0"),
        ("ior", math.nan, "ior"),
        ("color", (0.5, -1.0, 0.5), "color must be finite and >= 0"),
        ("color", "blue", "color must be 3 numbers"),
    ):
        with pytest.raises(MaterialError, match=message) as caught:
            setattr(glass, parameter, value)
        assert caught.value.parameter == parameter
    assert (glass.ior, glass.color, glass.version) == (1.33, (0.9, 0.9, 0.9), 1)
    glass.name = "renamed"  # names never reach the GPU
    assert glass.version == 1
    glossy = Glossy("metal")
    glossy.roughness = 0.5
    assert glossy.roughness == 0.5 and glossy.version == 1


def test_shapes_are_added_removed_and_found_by_name(box):
    other = make_box((2, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("red"), "other")
    scene = Scene([box])
    scene.add(other)
    assert scene.shape("other") is other and scene.triangle_count == 24
    scene.remove("box")
    assert scene.shapes == [other]
    with pytest.raises(SceneError, match="no shape called 'box'"):
        scene.remove("box")
    with pytest.raises(SceneError, match="not in the scene"):
        scene.remove(box)
    scene.add(make_box((4, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("red"), "other"))
    with pytest.raises(SceneError, match="2 shapes called 'other'"):
        scene.shape("other")


def test_scene_rejects_what_is_not_a_shape_or_camera(box):
    scene = Scene([box])
    with pytest.raises(SceneError, match="shapes\\[1\\] is a str"):
        scene.add("a box")
    with pytest.raises(SceneError, match="camera must be a Camera"):
        scene.camera = (0, 0, 0)
    scene.shapes.append(42)  # the list itself is open; arrays() still checks it
    with pytest.raises(SceneError, match="shapes\\[1\\] is a int"):
        scene.arrays()
    with pytest.raises(SceneError, match="material must be a Material"):
        box.material = "red"
    scene.camera = Camera((0, 0, -3), (0, 0, 1), (0, 1, 0), 50.0)


def test_empty_scene_after_removing_everything_is_an_error(box):
    scene = Scene([box]).remove(box)
    with pytest.raises(SceneError, match="no triangles"):
        scene.arrays()


def test_emitter_radiance_is_bounded_so_gpu_sums_stay_finite():
    lamp = Emitter("lamp", color=(1.0, 0.5, 0.5), emittance=1e20)
    with pytest.raises(MaterialError, match="radiance color x emittance = 2e\\+20 exceeds RADIANCE_MAX = 1e\\+20"):
        lamp.color = (2.0, 1.0, 1.0)
    assert lamp.color == (1.0, 0.5, 0.5)
