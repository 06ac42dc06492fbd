"""The G-buffer the path tracer writes for temporal accumulation (`write_gbuffer`): depth, surface
and motion vectors of a wall and a card seen by a moving pinhole camera against their closed
forms (wgputrace.testing.reprojection); nothing of it compiled in without it."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, EquirectangularCamera, OrthographicCamera, Renderer
from wgputrace.gpu.layout import FRAME, GBUFFER_PIXEL
from wgputrace.kernels.variant import KernelVariant
from wgputrace.testing.reprojection import SIZE, card_scene, centre_hits, pinhole, pixel_centres, raster_of

pytestmark = pytest.mark.gpu

# float32 rays and projections of points a few units away: far below a pixel's thousandth
MOTION_TOLERANCE_PIXELS = 1e-3
DEPTH_RELATIVE_TOLERANCE = 1e-5


@pytest.mark.parametrize(
    ("step", "yaw_degrees", "aperture_radius"),
    [(0.3, 0.0, 0.0), (0.1, 7.0, 0.0), (0.1, 7.0, 0.05)],
    ids=["sideways", "turning", "thin lens"],
)
def test_motion_vectors_are_where_the_previous_camera_saw_each_point(step, yaw_degrees, aperture_radius):
    scene = card_scene(card=Diffuse("grey", color=(0.3, 0.3, 0.3)))
    renderer = Renderer(scene, SIZE, SIZE)
    previous, current = pinhole(0.0, 0.0, aperture_radius), pinhole(step, yaw_degrees, aperture_radius)
    renderer.render_frame(previous)
    renderer.render_frame(current)
    gbuffer = renderer.gbuffer()
    points, on_card = centre_hits(current)
    expected_motion = raster_of(previous, points) - pixel_centres()
    assert np.abs(gbuffer["motion"] - expected_motion).max() < MOTION_TOLERANCE_PIXELS
    distance = np.linalg.norm(points - current.position, axis=-1)
    np.testing.assert_allclose(gbuffer["depth"], distance, rtol=DEPTH_RELATIVE_TOLERANCE)
    previous_distance = np.linalg.norm(points - previous.position, axis=-1)
    np.testing.assert_allclose(gbuffer["previous_depth"], previous_distance, rtol=DEPTH_RELATIVE_TOLERANCE)
    assert gbuffer["previous_seen"].all()
    # the card and the wall are materials 1 and 0: surfaces 2 and 1
    np.testing.assert_array_equal(gbuffer["surface"], np.where(on_card, 2, 1))
    np.testing.assert_allclose(gbuffer["albedo"][on_card], 0.3, rtol=1e-6)
    np.testing.assert_allclose(gbuffer["normal"], np.broadcast_to([0.0, 0.0, -1.0], (SIZE, SIZE, 3)), atol=1e-6)


def test_an_orthographic_camera_moves_everything_by_its_step():
    renderer = Renderer(card_scene(), SIZE, SIZE)
    previous = OrthographicCamera(position=(0.0, 0.0, 0.0), forward=(0, 0, 1), up=(0, 1, 0), view_height=4.0)
    current = OrthographicCamera(position=(0.3, -0.2, 0.0), forward=(0, 0, 1), up=(0, 1, 0), view_height=4.0)
    renderer.render_frame(previous)
    renderer.render_frame(current)
    record = FRAME.zeros(1)
    current.fill_frame(record, SIZE, SIZE)
    right, up = record["camera_right"][0].astype(np.float64), record["camera_up"][0].astype(np.float64)
    step = np.subtract(current.position, previous.position)
    # the rectangle's half extents span half the image
    expected = (step @ right / (right @ right) * SIZE / 2, -(step @ up) / (up @ up) * SIZE / 2)
    motion = renderer.gbuffer()["motion"]
    assert np.abs(motion - expected).max() < MOTION_TOLERANCE_PIXELS


def test_an_equirectangular_camera_turning_moves_everything_by_its_angle():
    width, height = 2 * SIZE, SIZE
    turn_degrees = 22.5
    scene = card_scene()
    renderer = Renderer(scene, width, height)
    for yaw in (0.0, turn_degrees):
        forward = (np.sin(np.radians(yaw)), 0.0, np.cos(np.radians(yaw)))
        renderer.render_frame(EquirectangularCamera(position=(0.0, 0.0, 0.0), forward=forward, up=(0, 1, 0)))
    motion = renderer.gbuffer()["motion"]
    # a turn is a shift of the columns; points that crossed the image's left and right edge went
    # the other way round
    shift = np.abs(motion[..., 0])
    across = np.isclose(shift, width - turn_degrees / 360 * width, atol=MOTION_TOLERANCE_PIXELS)
    assert across.sum() == turn_degrees / 360 * width * height
    assert np.abs(shift[~across] - turn_degrees / 360 * width).max() < 2e-3
    # rows near the poles turn about the image's vertical axis too, to float32's rounding
    assert np.abs(motion[..., 1]).max() < 2e-3


def test_a_resting_camera_has_no_motion_at_all():
    renderer = Renderer(card_scene(), SIZE, SIZE)
    renderer.render_frame(pinhole(0.1, 5.0))
    renderer.render_frame()
    gbuffer = renderer.gbuffer()
    assert not gbuffer["motion"].any()
    np.testing.assert_array_equal(gbuffer["previous_depth"], gbuffer["depth"])


def test_the_sky_moves_with_the_cameras_turn_alone():
    renderer = Renderer(card_scene(), SIZE, SIZE)
    # turned far enough that the right of the image sees past the wall's edge
    previous, current = pinhole(0.0, 80.0), pinhole(0.5, 82.0)
    renderer.render_frame(previous)
    renderer.render_frame(current)
    gbuffer = renderer.gbuffer()
    sky = gbuffer["surface"] == 0
    assert sky.any()
    right, up, forward = current.image_plane(SIZE, SIZE)
    ndc = pixel_centres() / (SIZE / 2) - 1.0
    directions = forward + ndc[..., :1] * right - ndc[..., 1:] * up
    far_points = np.asarray(previous.position) + directions[sky] * 1e9
    expected = raster_of(previous, far_points) - pixel_centres()[sky]
    assert np.abs(gbuffer["motion"][sky] - expected).max() < 0.05
    assert not gbuffer["depth"][sky].any()


def test_without_frames_nothing_of_the_gbuffer_is_compiled_or_bound():
    renderer = Renderer(card_scene(), SIZE, SIZE)
    assert not renderer.variant.gbuffer
    assert "gbuffer" not in renderer.resources and "G-buffer" not in renderer.gpu_image_bytes
    renderer.render_frame()
    assert renderer.variant.gbuffer and "gbuffer" in renderer.resources
    assert renderer.gpu_image_bytes["G-buffer"] == SIZE * SIZE * GBUFFER_PIXEL.size
    assert "G-buffer" in renderer.variant.label


def test_an_integrator_without_a_gbuffer_is_refused():
    with pytest.raises(ValueError, match="bdpt integrator writes no G-buffer"):
        Renderer(card_scene(), SIZE, SIZE, integrator="bdpt").render_frame()
    with pytest.raises(ValueError, match="names no integrator"):
        KernelVariant(gbuffer=True)
