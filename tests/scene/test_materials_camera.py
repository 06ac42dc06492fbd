"""Material parameter checks and camera conventions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Glass, Glossy, Scene
from wgputrace.render.scene_records import material_records
from wgputrace.scene import MaterialError, SceneError


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Diffuse("d", color=(0.5, -0.1, 0.5)), "color must be finite and >= 0"),
        (lambda: Diffuse("d", color=(0.5, math.nan, 0.5)), "color must be finite"),
        (lambda: Diffuse("d", color=(1.5, 0.5, 0.5)), "must be <= 1"),
        (lambda: Glass("g", ior=0.0), r"ior must be in \(0"),
        (lambda: Glass("g", ior=math.inf), "ior"),
        (lambda: Glossy("m", roughness=-0.1), r"roughness must be in \[0"),
        (lambda: Glossy("m", roughness=math.nan), "roughness"),
        (lambda: Emitter("e", emittance=-1.0), "emittance"),
        (lambda: Diffuse("d", color=(1, 2)), "3 numbers"),
    ],
)
def test_bad_parameters_are_named(make, message):
    with pytest.raises(MaterialError, match=message):
        make()


def test_emitter_radiance_is_color_times_emittance():
    emitter = Emitter("lamp", color=(1.0, 0.5, 0.25), emittance=4.0)
    assert emitter.radiance == (4.0, 2.0, 1.0)
    assert tuple(Emitter.record_radiance(material_records([emitter]))[0]) == (4.0, 2.0, 1.0)


def test_camera_is_right_handed_and_spans_fov():
    camera = Camera((0, 0, 0), (0, 0, 1), (0, 1, 0), 90.0)
    right, up, forward = camera.basis()
    np.testing.assert_allclose(right, np.cross(forward, (0, 1, 0)))
    np.testing.assert_allclose(right, [-1, 0, 0])
    np.testing.assert_allclose(up, [0, 1, 0])
    right2, up2, _ = camera.image_plane(200, 100)
    np.testing.assert_allclose(np.linalg.norm(up2), 1.0)  # tan(45 deg)
    np.testing.assert_allclose(np.linalg.norm(right2), 2.0)  # times the aspect ratio


def test_camera_rejects_degenerate_input():
    with pytest.raises(ValueError, match="parallel"):
        Camera((0, 0, 0), (0, 1, 0), (0, 2, 0))
    with pytest.raises(ValueError, match="vfov"):
        Camera(vfov_degrees=180.0)
    with pytest.raises(ValueError, match="zero vector"):
        Camera(forward=(0, 0, 0))
    looking = Camera.looking_at((1, 2, 3), (1, 2, 5))
    np.testing.assert_allclose(looking.forward, [0, 0, 1])


def test_empty_scene_is_an_error():
    with pytest.raises(SceneError, match="no triangles"):
        Scene().arrays()
