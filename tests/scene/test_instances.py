"""Instances on the Python side: checked transforms (one-line errors naming the instance), the
scene's materials and bounds counting them, and `flattened` drawing the same triangles."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Instance, Scene, make_box, model_matrix
from wgputrace.scene import SceneError


@pytest.fixture
def mesh():
    return make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("white", (0.8, 0.8, 0.8)), "crate")


@pytest.mark.parametrize(
    ("transform", "problem"),
    [
        (np.diag([1.0, 0.0, 1.0, 1.0]), "determinant 0.0"),
        (np.full((4, 4), np.nan), "NaN or infinite entry"),
        (np.eye(3), "4x4 matrix"),
        (np.diag([-1.0, 1.0, 1.0, 1.0]), "transform mirrors"),
        ([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]], "affine"),
    ],
)
def test_a_bad_transform_is_one_line_naming_the_instance_and_the_problem(mesh, transform, problem):
    scene = Scene([mesh])
    with pytest.raises(SceneError, match=problem) as raised:
        scene.add_instance(mesh, transform, name="tree7")
    message = str(raised.value)
    assert message.startswith("instance 'tree7': ") and "\n" not in message
    assert scene.instances == []


def test_assigning_a_bad_transform_keeps_the_old_one(mesh):
    instance = Scene([mesh]).add_instance(mesh, model_matrix((1, 2, 3), (0, 0, 0), 1.0))
    before = instance.transform.copy()
    with pytest.raises(SceneError, match=r"instance 'crate\[0\]'.*determinant"):
        instance.transform = np.diag([1.0, 1.0, 0.0, 1.0])
    np.testing.assert_array_equal(instance.transform, before)
    assert instance.transform_version == 0
    instance.transform = model_matrix((0, 0, 0), (0, 0, 0), 2.0)
    assert instance.transform_version == 1


def test_an_instance_needs_a_shape_and_a_scene_holds_only_instances(mesh):
    with pytest.raises(SceneError, match="mesh must be a Shape"):
        Instance("x", "crate", np.eye(4))
    with pytest.raises(SceneError, match=r"instances\[0\] is a str"):
        Scene([mesh], instances=["crate"])


def test_materials_and_bounds_count_the_instances(mesh):
    ground = make_box((0, -1, 0), (0, 0, 0), (4, 0.1, 4), Diffuse("ground", (0.5, 0.5, 0.5)), "ground")
    scene = Scene([ground])
    scene.add_instance(mesh, model_matrix((10, 0, 0), (0, 0, 0), 2.0))
    assert [m.name for m in scene.materials] == ["ground", "white"]
    low, high = scene.bounds()
    np.testing.assert_allclose(high, [11, 1, 2])
    np.testing.assert_allclose(low, [-2, -1.05, -2])


def test_flattened_draws_the_instances_triangles_and_leaves_the_scene(mesh):
    scene = Scene([])
    transform = model_matrix((1, 0, 0), (0.3, 0.2, 0.1), (1.0, 2.0, 0.5))
    instance = scene.add_instance(mesh, transform, name="moved")
    flat = scene.flattened()
    assert flat.instances == [] and scene.instances == [instance]
    (shape,) = flat.shapes
    assert shape.name == "moved" and shape.material is mesh.material
    np.testing.assert_array_equal(shape.world_vertices, mesh.transformed(transform).world_vertices)
    scene.remove_instance(instance)
    with pytest.raises(SceneError, match="not in the scene"):
        scene.remove_instance(instance)
