"""Fly-camera navigation: keys move along the view's axes for the time they are held, drags turn,
the wheel scales speed, R resets and F frames the scene (every camera kind); the aperture keys open
and close a lens on the pinhole, a click's focus waits for the lens."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Camera, EquirectangularCamera, OrthographicCamera, ThinLensCamera
from wgputrace.app.controls import (
    APERTURE_FIRST_FRACTION,
    APERTURE_STEP,
    LOOK_RADIANS_PER_PIXEL,
    PITCH_LIMIT,
    SPEED_STEP,
    WHEEL_NOTCH,
    FlyCamera,
)

BOUNDS = (np.array([-1.0, 0.0, -1.0]), np.array([1.0, 2.0, 1.0]))


@pytest.fixture
def fly():
    return FlyCamera(Camera((0.0, 1.0, -3.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0), 60.0), BOUNDS)


def test_keys_move_along_the_view_axes_for_the_time_held(fly):
    start = fly.position.copy()
    fly.press("w", 10.0)
    assert fly.move(10.5)
    fly.release("w", 11.0)  # released before any later frame: the last half second still counts
    assert fly.move(12.0)
    np.testing.assert_allclose(fly.position - start, (0.0, 0.0, fly.speed * 1.0))
    fly.press("d", 20.0)
    fly.release("d", 20.25)
    fly.press("e", 20.0)
    fly.release("e", 20.5)
    fly.move(21.0)
    # image right is cross(forward, up) = cross(+z, +y) = -x
    np.testing.assert_allclose(fly.position - start, (-0.25 * fly.speed, 0.5 * fly.speed, fly.speed))
    assert not fly.move(22.0)


def test_drag_turns_right_and_up_and_stops_short_of_the_pole(fly):
    fly.look(100.0, 0.0)
    angle = 100.0 * LOOK_RADIANS_PER_PIXEL
    np.testing.assert_allclose(fly.forward, (-math.sin(angle), 0.0, math.cos(angle)), atol=1e-12)
    fly.look(0.0, -1e6)  # dragging up looks up, as far as the limit
    assert fly.pitch == pytest.approx(PITCH_LIMIT)
    fly.camera()  # still a valid camera: forward never parallel to up


def test_wheel_scales_speed_and_reset_restores_everything(fly):
    home_speed = fly.speed
    fly.wheel(-2 * WHEEL_NOTCH)
    assert fly.speed == pytest.approx(home_speed * SPEED_STEP**2)
    fly.look(30.0, 20.0)
    fly.press("w", 0.0)
    fly.move(1.0)
    fly.reset()
    assert fly.speed == home_speed
    camera = fly.camera()
    np.testing.assert_allclose(camera.position, (0.0, 1.0, -3.0))
    np.testing.assert_allclose(camera.forward, (0.0, 0.0, 1.0), atol=1e-12)


@pytest.mark.parametrize("aspect", [0.5, 1.0, 16 / 9])
def test_frame_puts_every_corner_of_the_scene_in_view(fly, aspect):
    fly.look(200.0, 50.0)
    direction = fly.forward
    fly.frame_scene(aspect)
    np.testing.assert_allclose(fly.forward, direction)
    camera = fly.camera()
    height = 100
    right, up, forward = camera.image_plane(round(aspect * height), height)
    corners = np.array([[BOUNDS[(k >> axis) & 1][axis] for axis in range(3)] for k in range(8)])
    offsets = corners - camera.position
    depth = offsets @ forward
    assert np.all(depth > 0)
    ndc = np.stack([offsets @ right / (right @ right), offsets @ up / (up @ up)], axis=1) / depth[:, None]
    # the bounding sphere just fits, so the box's corners lie inside, some of them near the edge
    assert np.abs(ndc).max() <= 1.0
    assert np.abs(ndc).max() > 0.5


def test_the_aperture_keys_open_a_lens_on_the_pinhole_and_close_it_again(fly):
    assert fly.aperture_radius == 0.0 and type(fly.camera()) is Camera
    assert fly.step_aperture(1)
    lens = fly.camera()
    assert isinstance(lens, ThinLensCamera)
    assert lens.aperture_radius == pytest.approx(APERTURE_FIRST_FRACTION * fly.scene_size)
    # before any click it focuses where the scene's centre lies along the view
    assert lens.focus_distance == pytest.approx(3.0)
    fly.step_aperture(2)
    assert fly.camera().aperture_radius == pytest.approx(lens.aperture_radius * APERTURE_STEP**2)
    fly.step_aperture(-2)
    assert fly.camera().aperture_radius == pytest.approx(lens.aperture_radius)
    fly.step_aperture(-1)
    assert type(fly.camera()) is Camera  # back to the pinhole, whose kernel draws no lens sample
    assert fly.camera() == Camera(tuple(fly.position), tuple(fly.forward), tuple(fly.world_up), 60.0)


def test_focus_is_kept_for_the_lens_to_come_and_reset_restores_the_scenes_camera(fly):
    fly.focus_at(1.25)
    fly.step_aperture(1)
    assert fly.camera().focus_distance == 1.25
    fly.focus_at(2.5)
    assert fly.camera().focus_distance == 2.5
    fly.reset()
    assert type(fly.camera()) is Camera and fly.focus_distance == pytest.approx(3.0)


@pytest.mark.parametrize(
    "camera",
    [
        OrthographicCamera((0.0, 1.0, -3.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0), view_height=1.0),
        EquirectangularCamera((0.0, 1.0, -3.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
    ],
    ids=type,
)
def test_cameras_without_a_lens_keep_their_kind(camera):
    fly = FlyCamera(camera, BOUNDS)
    assert fly.aperture_radius is None and not fly.step_aperture(1)
    fly.look(10.0, 0.0)
    assert type(fly.camera()) is type(camera)


@pytest.mark.parametrize("aspect", [0.5, 2.0])
def test_frame_widens_an_orthographic_view_to_the_scene(aspect):
    fly = FlyCamera(OrthographicCamera((0.0, 1.0, -3.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0), view_height=0.1), BOUNDS)
    fly.frame_scene(aspect)
    camera = fly.camera()
    right, up = camera.half_extents(round(aspect * 100), 100)
    corners = np.array([[BOUNDS[(k >> axis) & 1][axis] for axis in range(3)] for k in range(8)])
    offsets = corners - camera.position
    assert np.all(offsets @ np.asarray(camera.forward) > 0)
    ndc = np.stack([offsets @ right / (right @ right), offsets @ up / (up @ up)], axis=1)
    assert np.abs(ndc).max() <= 1.0 and np.abs(ndc).max() > 0.5
