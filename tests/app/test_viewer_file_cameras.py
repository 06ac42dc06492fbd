"""The viewer's C key on the offscreen canvas: it steps through the scene file's own cameras
(`Scene.cameras`), the orthographic one compiled in as its kind, its name in the overlay's status;
`--camera` starts from another; a scene without cameras of its own says so."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, OrthographicCamera
from wgputrace.testing.gltf_files import box_with_cameras
from wgputrace.testing.offscreen_viewer import frames, offscreen_viewer

pytestmark = pytest.mark.gpu

# Frames after a key for the renderer to have taken the camera (the first restarts the picture).
FRAMES_AFTER_KEY = 2


def shown_camera(viewer):
    frames(viewer, FRAMES_AFTER_KEY)
    return viewer.view.renderer.scene.camera


def test_c_steps_through_the_file_cameras_and_names_them(gpu_context, tmp_path):
    viewer = offscreen_viewer(str(box_with_cameras(tmp_path / "box.glb")), tmp_path)
    assert type(shown_camera(viewer)) is Camera
    viewer.input.press("c")
    top = shown_camera(viewer)
    assert viewer.overlay.status == "camera 1 of 2: top"
    assert isinstance(top, OrthographicCamera) and top.view_height == pytest.approx(3.0)
    np.testing.assert_allclose(top.position, [0, 5, 0])
    assert "OrthographicCamera" in viewer.view.renderer.variant.label
    viewer.input.press("C")  # with Shift as without
    front = shown_camera(viewer)
    assert viewer.overlay.status == "camera 0 of 2: front"
    assert type(front) is Camera and front.position == pytest.approx((0, 0.5, 6))
    assert "OrthographicCamera" not in viewer.view.renderer.variant.label


def test_the_camera_option_starts_from_another_and_r_returns_to_it(gpu_context, tmp_path):
    viewer = offscreen_viewer(str(box_with_cameras(tmp_path / "box.glb")), tmp_path, camera="top")
    assert isinstance(shown_camera(viewer), OrthographicCamera)
    viewer.input.look(40.0, 0.0)
    viewer.input.press("r")
    np.testing.assert_allclose(shown_camera(viewer).forward, [0, -1, 0], atol=1e-9)
    viewer.input.press("c")
    assert viewer.overlay.status == "camera 0 of 2: front"
    assert type(shown_camera(viewer)) is Camera


def test_a_scene_without_cameras_of_its_own_says_so(gpu_context, tmp_path):
    viewer = offscreen_viewer("cornell", tmp_path)
    before = shown_camera(viewer)
    viewer.input.press("c")
    assert viewer.overlay.status == "the scene brings no cameras of its own"
    assert shown_camera(viewer) == before
