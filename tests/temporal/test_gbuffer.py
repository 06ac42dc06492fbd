"""The G-buffer the path tracer writes for temporal accumulation (`write_gbuffer`): depth, surface
and motion vectors of a wall and a card seen by a moving pinhole camera against their closed
forms (wgputrace.testing.reprojection); nothing of it compiled in without it."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Renderer
from wgputrace.gpu.layout import GBUFFER_PIXEL
from wgputrace.kernels.variant import KernelVariant
from wgputrace.testing.reprojection import SIZE, card_scene, centre_hits, pinhole, pixel_centres, raster_of

pytestmark = pytest.mark.gpu

# float32 rays and projections of points a few units away: far below a pixel's thousandth
MOTION_TOLERANCE_PIXELS = 1e-3
DEPTH_RELATIVE_TOLERANCE = 1e-5


@pytest.mark.parametrize(("step", "yaw_degrees"), [(0.3, 0.0), (0.1, 7.0)], ids=["sideways", "turning"])
def test_motion_vectors_are_where_the_previous_camera_saw_each_point(step, yaw_degrees):
    scene = card_scene(card=Diffuse("grey", color=(0.3, 0.3, 0.3)))
    renderer = Renderer(scene, SIZE, SIZE)
    previous, current = pinhole(0.0), pinhole(step, yaw_degrees)
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
