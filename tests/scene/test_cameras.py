"""The camera kinds' parameters and checks, their descriptions, Mitsuba 3 sensors and clip
matrices (pure numpy; the shaders' side is tests/shaders/test_camera_rays.py)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.scene import CameraError, CameraWarning, Scene, SceneError, camera_classes
from wgputrace.testing.camera_rays import camera_rays

POSE = ((0.3, -0.2, 1.0), (0.2, -0.1, 1.0), (0.1, 1.0, 0.05))
WIDTH, HEIGHT = 8, 6
# the parameters each kind requires
REQUIRED = {
    wt.Camera: {},
    wt.ThinLensCamera: {"aperture_radius": 0.1, "focus_distance": 1.0},
    wt.OrthographicCamera: {"view_height": 1.0},
    wt.EquirectangularCamera: {},
}


def test_every_kind_is_registered_and_exported():
    names = [cls.__name__ for cls in camera_classes()]
    assert names == ["Camera", "ThinLensCamera", "OrthographicCamera", "EquirectangularCamera"]
    assert all(getattr(wt, name) is cls for name, cls in zip(names, camera_classes(), strict=True))
    assert issubclass(wt.ThinLensCamera, wt.Camera) and issubclass(wt.OrthographicCamera, wt.Sensor)


@pytest.mark.parametrize(
    "make, parameter, message",
    [
        (lambda: wt.ThinLensCamera(aperture_radius=-0.1, focus_distance=1.0), "aperture_radius", ">= 0, got -0.1"),
        (lambda: wt.ThinLensCamera(aperture_radius=math.nan, focus_distance=1.0), "aperture_radius", "got nan"),
        (lambda: wt.ThinLensCamera(aperture_radius=0.1, focus_distance=0.0), "focus_distance", "> 0, got 0.0"),
        (lambda: wt.ThinLensCamera(aperture_radius=0.1, focus_distance=-2), "focus_distance", "> 0, got -2"),
        (lambda: wt.ThinLensCamera(aperture_radius=0.1, focus_distance=math.inf), "focus_distance", "got inf"),
        (lambda: wt.ThinLensCamera(aperture_radius="wide", focus_distance=1.0), "aperture_radius", "got 'wide'"),
        (lambda: wt.OrthographicCamera(view_height=math.nan), "view_height", "> 0, got nan"),
        (lambda: wt.OrthographicCamera(view_height=0), "view_height", "> 0, got 0"),
        (lambda: wt.Camera(vfov_degrees=math.nan), "vfov_degrees", r"\(0, 180\), got nan"),
        (lambda: wt.EquirectangularCamera(position=(0, math.nan, 0)), "position", "3 finite numbers"),
        (lambda: wt.EquirectangularCamera(forward=(0, 0, 0)), "forward", "zero vector"),
        (lambda: wt.OrthographicCamera(up=(0, 0, 2), view_height=1), "up", "parallel to forward"),
    ],
)
def test_bad_parameters_are_one_line_errors_naming_the_field(make, parameter, message):
    with pytest.raises(CameraError, match=message) as raised:
        make()
    assert raised.value.parameter == parameter
    assert parameter in str(raised.value) and "\n" not in str(raised.value)
    assert isinstance(raised.value, SceneError)


def test_an_edit_is_checked_and_a_bad_one_changes_nothing():
    camera = wt.ThinLensCamera.looking_at((0, 0, 0), (0, 0, 4), aperture_radius=0.1)
    assert camera.focus_distance == 4.0  # in focus at the target
    camera.aperture_radius = 0.2
    assert camera.version == 1
    with pytest.raises(CameraError, match="aperture_radius"):
        camera.aperture_radius = -1.0
    assert camera.aperture_radius == 0.2 and camera.version == 1
    camera.forward = (0, 0, 3)
    assert camera.forward == (0.0, 0.0, 1.0)  # normalised when set


def test_posed_keeps_the_kind_and_its_parameters():
    camera = wt.OrthographicCamera(*POSE, view_height=2.5)
    moved = camera.posed((1, 2, 3), (1, 0, 0), (0, 1, 0))
    assert type(moved) is wt.OrthographicCamera and moved.view_height == 2.5
    assert moved.position == (1.0, 2.0, 3.0) and moved.forward == (1.0, 0.0, 0.0)


def test_scene_takes_every_kind_and_names_them_when_refusing():
    scene = Scene()
    for cls in camera_classes():
        scene.camera = cls(**REQUIRED[cls])
        assert scene.camera.kind == cls.kind
    with pytest.raises(SceneError, match="camera must be a Camera or another camera kind .*EquirectangularCamera"):
        scene.camera = "camera"


def test_descriptions_name_the_kind_and_every_parameter():
    camera = wt.ThinLensCamera((0, 1, 0), (0, 0, 1), (0, 1, 0), 40.0, aperture_radius=0.05, focus_distance=3)
    assert camera.description() == (
        "ThinLensCamera: position 0,1,0, forward 0,0,1, up 0,1,0, vfov_degrees 40, aperture_radius 0.05, "
        "focus_distance 3"
    )


def test_mitsuba_sensors():
    lens = wt.ThinLensCamera(*POSE, 40.0, aperture_radius=0.05, focus_distance=3.0)
    sensor = lens.mitsuba_sensor(WIDTH, HEIGHT)
    assert (sensor["type"], sensor["fov"], sensor["fov_axis"]) == ("thinlens", 40.0, "y")
    assert (sensor["aperture_radius"], sensor["focus_distance"]) == (0.05, 3.0)
    np.testing.assert_allclose(sensor["to_world"]["look_at"]["target"], np.add(lens.position, lens.forward))
    # Mitsuba's orthographic film spans [-1, 1] across and [-1 / aspect, 1 / aspect] down, scaled
    ortho = wt.OrthographicCamera(*POSE, view_height=3.0).mitsuba_sensor(WIDTH, HEIGHT)
    assert ortho["type"] == "orthographic"
    assert ortho["to_world"]["scale"] == pytest.approx((1.5 * WIDTH / HEIGHT, 1.5 * WIDTH / HEIGHT, 1.0))
    assert wt.EquirectangularCamera(*POSE).mitsuba_sensor(WIDTH, HEIGHT) is None


@pytest.mark.parametrize(
    "camera",
    [wt.Camera(*POSE, 50.0), wt.ThinLensCamera(*POSE, 50.0, aperture_radius=0.3, focus_distance=2.0)]
    + [wt.OrthographicCamera(*POSE, view_height=1.5)],
    ids=type,
)
def test_clip_matrix_puts_points_where_the_rays_through_their_lens_centre_land(rng, camera):
    pixels = np.stack([rng.integers(0, WIDTH, 32), rng.integers(0, HEIGHT, 32)], axis=1)
    jitter = rng.random((32, 2))
    origins, directions = camera_rays(camera, WIDTH, HEIGHT, pixels, jitter, np.full((32, 2), 0.5))
    points = origins + rng.uniform(0.5, 5.0, (32, 1)) * directions
    clip = camera.clip_matrix(WIDTH, HEIGHT, 0.01, 100.0) @ np.append(points, np.ones((32, 1)), axis=1).T
    ndc = (clip[:2] / clip[3]).T
    expected = (pixels + jitter) / (WIDTH, HEIGHT) * 2.0 - 1.0
    np.testing.assert_allclose(ndc, expected * (1, -1), atol=1e-5)
    assert ((clip[2] / clip[3] > 0) & (clip[2] / clip[3] < 1)).all()


def test_equirectangular_images_not_two_by_one_warn():
    camera = wt.EquirectangularCamera()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        camera.check_image(64, 32)
    with pytest.warns(CameraWarning, match="a 64x64 image is not 2:1 \\(128x64 would be\\)"):
        camera.check_image(64, 64)
    assert camera.clip_matrix(64, 32, 0.1, 10.0) is None
