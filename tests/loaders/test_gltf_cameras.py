"""A glTF file's cameras: every camera its nodes place is in `Scene.cameras` at its node's world
transform (parents' scales included; a camera placed twice is two), chosen by name or index with
`load_scene(..., camera=...)`, and a value outside glTF's range is an error naming its JSON path."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from wgputrace import Camera, OrthographicCamera, SceneLoadError, load_scene
from wgputrace.testing.gltf_files import (
    BOX,
    BOX_INDICES,
    CAMERA_NODES,
    CAMERAS,
    box_with_cameras,
    gltf_document,
    with_cameras,
    write_glb,
)


def cameras_glb(tmp_path, cameras: list[dict], nodes: list[dict]):
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    return write_glb(tmp_path / "cameras.glb", with_cameras(document, cameras, nodes), blob)


def copied(value):
    return json.loads(json.dumps(value))


def test_every_camera_is_listed_and_the_first_is_the_scene_camera(tmp_path):
    scene = load_scene(box_with_cameras(tmp_path / "box.glb"))
    assert [name for name, _ in scene.cameras] == ["front", "top"]
    (_, front), (_, top) = scene.cameras
    assert scene.camera is front
    assert type(front) is Camera and front.vfov_degrees == pytest.approx(math.degrees(0.7))
    np.testing.assert_allclose(front.position, [0, 0.5, 6])
    assert isinstance(top, OrthographicCamera) and top.view_height == pytest.approx(3.0)
    np.testing.assert_allclose(top.position, [0, 5, 0])
    np.testing.assert_allclose(top.forward, [0, -1, 0], atol=1e-12)


@pytest.mark.parametrize("choice", ["top", 1, "1", np.int64(1)])
def test_a_camera_is_chosen_by_name_or_index(tmp_path, choice):
    scene = load_scene(box_with_cameras(tmp_path / "box.glb"), camera=choice)
    assert scene.camera is scene.cameras[1][1]


def test_a_name_is_matched_before_an_index(tmp_path):
    cameras = copied(CAMERAS)
    cameras[1]["name"] = "0"
    scene = load_scene(cameras_glb(tmp_path, cameras, copied(CAMERA_NODES)), camera="0")
    assert scene.camera is scene.cameras[1][1]


@pytest.mark.parametrize("choice", ["side", 2, "2", -1, "-1"])
def test_an_unknown_camera_lists_the_cameras_there_are(tmp_path, choice):
    path = box_with_cameras(tmp_path / "box.glb")
    with pytest.raises(SceneLoadError) as raised:
        load_scene(path, camera=choice)
    message = str(raised.value)
    assert message == f"{path}: no camera {choice!r}; its cameras: 0 'front', 1 'top'"


def test_a_name_two_cameras_share_asks_for_the_index(tmp_path):
    nodes = [*copied(CAMERA_NODES), {"camera": 1, "translation": [3, 5, 0]}]
    path = cameras_glb(tmp_path, copied(CAMERAS), nodes)
    with pytest.raises(SceneLoadError, match=r"2 cameras are called 'top' \(indices \[1, 2\]\): give its index"):
        load_scene(path, camera="top")
    assert load_scene(path, camera=2).camera.position == (3.0, 5.0, 0.0)


def test_a_file_without_cameras_is_framed_and_refuses_a_choice(tmp_path):
    path = cameras_glb(tmp_path, [], [])
    scene = load_scene(path)
    assert scene.cameras == [] and scene.camera.forward == (0.0, 0.0, -1.0)
    with pytest.raises(SceneLoadError, match=r"no camera 'front'; the scene brings no cameras of its own$"):
        load_scene(path, camera="front")


def test_a_built_in_scene_has_no_cameras_to_choose(tmp_path):
    with pytest.raises(SceneLoadError, match=r"^no camera 0; the scene brings no cameras of its own$"):
        load_scene("cornell", camera=0)


def test_a_camera_object_still_replaces_the_file_cameras(tmp_path):
    own = Camera((1, 2, 3), (0, 0, -1))
    assert load_scene(box_with_cameras(tmp_path / "box.glb"), camera=own).camera is own


def test_cameras_take_their_node_world_transform_scale_and_all(tmp_path):
    """A parent scaled by 2 and moved places its child cameras: positions in world space, the
    orthographic view's height scaled by the world y scale; the perspective's angle is not scaled.
    One camera placed by two nodes is two cameras; names fall back to the node's, then the path."""
    cameras = copied(CAMERAS)
    del cameras[0]["name"]
    nodes = [
        {"translation": [10, 0, 0], "scale": [2, 2, 2], "children": [2, 3, 4]},
        {"camera": 0, "name": "child", "translation": [0, 0, 3]},
        {"camera": 1, "translation": [0, 1, 0], "rotation": CAMERA_NODES[1]["rotation"]},
        {"camera": 0, "translation": [1, 0, 0]},
    ]
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    document["cameras"] = cameras
    document["nodes"] += nodes
    document["scenes"][0]["nodes"].append(1)
    scene = load_scene(write_glb(tmp_path / "scaled.glb", document, blob))
    assert [name for name, _ in scene.cameras] == ["child", "top", "cameras[0]"]
    (_, child), (_, top), (_, again) = scene.cameras
    np.testing.assert_allclose(child.position, [10, 0, 6])
    np.testing.assert_allclose(again.position, [12, 0, 0])
    assert child.vfov_degrees == again.vfov_degrees == pytest.approx(math.degrees(0.7))
    np.testing.assert_allclose(top.position, [10, 2, 0])
    assert top.view_height == pytest.approx(2 * 1.5 * 2)


# (camera kind, field, value, the error's problem)
BAD_VALUES = [
    ("perspective", "yfov", 0, "must be in (0, pi) radians, got 0.0"),
    ("perspective", "yfov", -0.5, "must be in (0, pi) radians, got -0.5"),
    ("perspective", "yfov", math.pi, f"must be in (0, pi) radians, got {math.pi!r:.20}"),
    ("perspective", "aspectRatio", 0, "must be > 0, got 0.0"),
    ("perspective", "znear", 0, "must be > 0, got 0.0"),
    ("perspective", "znear", -1, "must be > 0, got -1.0"),
    ("perspective", "zfar", 0.05, "must be > znear (0.1), got 0.05"),
    ("orthographic", "xmag", 0, "must be a number other than 0, got 0.0"),
    ("orthographic", "ymag", 0, "must be a number other than 0, got 0.0"),
    ("orthographic", "znear", -0.5, "must be >= 0, got -0.5"),
    ("orthographic", "ymag", "wide", "must be float, got 'wide'"),
]


@pytest.mark.parametrize(("kind", "field", "value", "problem"), BAD_VALUES)
def test_a_bad_camera_value_names_its_json_path(tmp_path, kind, field, value, problem):
    cameras = copied(CAMERAS)
    index = 0 if kind == "perspective" else 1
    cameras[index][kind][field] = value
    path = cameras_glb(tmp_path, cameras, copied(CAMERA_NODES))
    with pytest.raises(SceneLoadError) as raised:
        load_scene(path)
    assert str(raised.value) == f"{path}: cameras[{index}].{kind}.{field}: {problem}"


def test_a_missing_yfov_is_named(tmp_path):
    cameras = copied(CAMERAS)
    del cameras[0]["perspective"]["yfov"]
    path = cameras_glb(tmp_path, cameras, copied(CAMERA_NODES))
    with pytest.raises(SceneLoadError, match=r"cameras\[0\]\.perspective: 'yfov' is missing$"):
        load_scene(path)


def test_a_node_scaled_flat_is_named(tmp_path):
    nodes = copied(CAMERA_NODES)
    nodes[0]["scale"] = [1, 1, 0]
    path = cameras_glb(tmp_path, copied(CAMERAS), nodes)
    with pytest.raises(SceneLoadError, match=r"cameras\[0\] at nodes\[1\]: .*forward"):
        load_scene(path)
