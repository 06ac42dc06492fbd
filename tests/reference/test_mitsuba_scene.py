"""The Mitsuba scene built from ours (`mitsuba_scene`) holds the same
triangles, emitters and camera, whatever its kind. Needs mitsuba (the `reference` extra), which CI
does not install."""

from __future__ import annotations

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.reference.mitsuba_scene import (
    EMITTER_BACK_OFFSET_RELATIVE,
    NEAR_CLIP_RELATIVE,
    SCALAR_VARIANT,
    load_mitsuba,
    mitsuba_scene,
    sensor_dict,
)
from wgputrace.scenes import scene_by_name
from wgputrace.testing.camera_rays import camera_rays

pytest.importorskip("mitsuba", reason="Mitsuba 3 (the reference extra) is not installed")

SIZE = 8
MAX_DEPTH = 9
# Mitsuba stores vertices as float32, as we do: bounds agree to float32 rounding of coordinates ~1.
COORDINATE_ATOL = 1e-6
# The centre pixel's ray leaves the camera along its forward axis, up to float32 rounding in
# Mitsuba's camera transforms.
DIRECTION_ATOL = 1e-5


@pytest.fixture(scope="module")
def mi():
    # the scalar variant needs no LLVM, and this test renders nothing
    return load_mitsuba(SCALAR_VARIANT)


@pytest.mark.parametrize("name", ["cornell", "tiny_light", "glass_grazing"])
def test_same_triangles_and_emitters(mi, name):
    ours = scene_by_name(name)
    arrays = ours.arrays()
    theirs = mitsuba_scene(mi, ours, SIZE, SIZE, MAX_DEPTH)
    emitter_triangles = sum(
        int(np.count_nonzero(arrays.material_index == index))
        for index, material in enumerate(arrays.materials)
        if material.emission_wgsl is not None
    )
    shapes = theirs.shapes()
    # every emitter triangle twice: Mitsuba's area lights shine from the front only, ours both ways
    assert sum(shape.face_count() for shape in shapes) == len(arrays.vertices) + emitter_triangles
    assert sum(shape.face_count() for shape in shapes if shape.is_emitter()) == 2 * emitter_triangles

    corners = arrays.vertices.reshape(-1, 3)
    back_offset = EMITTER_BACK_OFFSET_RELATIVE * float(np.max(np.abs(corners)))
    box = theirs.bbox()
    np.testing.assert_allclose(np.array(box.min), corners.min(axis=0), atol=back_offset + COORDINATE_ATOL)
    np.testing.assert_allclose(np.array(box.max), corners.max(axis=0), atol=back_offset + COORDINATE_ATOL)


def test_same_camera(mi):
    ours = scene_by_name("cornell")
    sensor = mitsuba_scene(mi, ours, SIZE, SIZE, MAX_DEPTH).sensors()[0]
    centre = mi.Point2f(0.5, 0.5)
    ray, _ = sensor.sample_ray(0.0, 0.5, centre, centre)
    # Mitsuba's rays start at the near clip plane
    corners = ours.arrays().vertices.reshape(-1, 3)
    near_clip = NEAR_CLIP_RELATIVE * float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
    np.testing.assert_allclose(np.array(ray.o), ours.camera.position, atol=near_clip + COORDINATE_ATOL)
    np.testing.assert_allclose(np.array(ray.d), ours.camera.forward, atol=DIRECTION_ATOL)
    # the top-left corner of the film lies up and to the left (image right = cross(forward, up))
    corner, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(0.0, 0.0), centre)
    right = np.cross(ours.camera.forward, ours.camera.up)
    assert np.dot(np.array(corner.d), right) < 0.0
    assert np.dot(np.array(corner.d), ours.camera.up) > 0.0


# Tilted poses, so that no basis vector is an axis; a film that is not square.
POSE = ((0.3, -0.2, 1.0), (0.2, -0.1, 1.0), (0.1, 1.0, 0.05))
FILM = (8, 6)
FILM_POINTS = ((0.5, 0.5), (0.0, 0.0), (1.0, 0.25), (0.2, 0.9))


@pytest.mark.parametrize(
    "camera",
    [
        wt.Camera(*POSE, 35.0),
        wt.ThinLensCamera(*POSE, 35.0, aperture_radius=0.2, focus_distance=2.5),
        wt.OrthographicCamera(*POSE, view_height=1.7),
    ],
    ids=lambda camera: type(camera).__name__,
)
def test_every_camera_kind_is_mitsubas_sensor(mi, camera):
    """Through the lens's centre Mitsuba's rays are ours (`camera_rays`, at the near clip plane);
    a thin lens's rays from anywhere on the lens meet ours at the plane in focus."""
    width, height = FILM
    sensor = mi.load_dict(
        {**sensor_dict(mi, camera, width, height), "film": {"type": "hdrfilm", "width": width, "height": height}}
    )
    centre = mi.Point2f(0.5, 0.5)
    for point in FILM_POINTS:
        pixel_point = np.array(point) * FILM
        origin, direction = camera_rays(
            camera, width, height, np.floor(pixel_point)[None], (pixel_point % 1)[None], [(0.5, 0.5)]
        )
        ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(*point), centre)
        near = float(np.dot(np.array(ray.o) - origin[0], direction[0]))
        np.testing.assert_allclose(np.array(ray.o), origin[0] + near * direction[0], atol=COORDINATE_ATOL)
        np.testing.assert_allclose(np.array(ray.d), direction[0], atol=DIRECTION_ATOL)
        if isinstance(camera, wt.ThinLensCamera):
            focus = origin[0] + camera.focus_distance / float(direction[0] @ camera.forward) * direction[0]
            off_centre, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(*point), mi.Point2f(0.9, 0.2))
            o, d = np.array(off_centre.o), np.array(off_centre.d)
            np.testing.assert_allclose(o + float((focus - o) @ d) * d, focus, atol=1e-5)
            assert np.linalg.norm(o - origin[0]) > 0.05  # it did leave from elsewhere on the lens
