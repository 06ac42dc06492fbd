"""Moving objects in temporal accumulation (ObjectMotion, the G-buffer's `object_motion`): a card
turning and sliding in its plane, as a shape and as an instance, moves its pixels' motion vectors
to where the previous frame saw each point of it (closed form from its two transforms); a card
sliding across the wall keeps its own history, loses the wall's exactly where it had covered it,
and leaves none of its colour behind; the motion records exist only for frames and upload only the
rows that changed."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Emitter, Renderer
from wgputrace.gpu.layout import OBJECT_MOTION
from wgputrace.render.object_motion import OBJECT_MOTIONS, TRIANGLE_OBJECTS
from wgputrace.testing.reprojection import (
    CARD_ROWS,
    SIZE,
    card_move,
    card_object,
    card_scene,
    centre_hits,
    moved_points,
    pinhole,
    pixel_centres,
    raster_of,
)

pytestmark = pytest.mark.gpu

# float32 points a few units away through two transforms and a projection
MOTION_TOLERANCE_PIXELS = 1e-3
FRAMES_AT_REST = 3
# whole pixels, so each of the card's pixels reprojects onto one previous pixel of it
SLIDE_PIXELS = 3
KINDS = {"ids": ["shape", "instance"], "argnames": "instanced", "argvalues": [False, True]}
GREY = Diffuse("grey", color=(0.3, 0.3, 0.3))


@pytest.mark.parametrize(**KINDS)
def test_a_moving_cards_motion_vectors_follow_its_transform(instanced):
    scene = card_scene(card=GREY, instanced=instanced)
    renderer = Renderer(scene, SIZE, SIZE)
    before, after = card_move((1.5, -0.7), 4.0), card_move((3.2, 0.4), 11.0)
    card_object(scene).transform = before
    renderer.render_frame(pinhole(0.0))
    card_object(scene).transform = after
    renderer.render_frame()
    gbuffer = renderer.gbuffer()
    points, on_card = centre_hits(pinhole(0.0), card=after)
    # the wall is shape 0; the card shape 1, or instance 0 after the one shape
    np.testing.assert_array_equal(gbuffer["object"], np.where(on_card, 1, 0))
    previous = moved_points(points, before @ np.linalg.inv(after))
    expected = raster_of(pinhole(0.0), previous) - pixel_centres()
    assert np.abs(gbuffer["motion"][on_card] - expected[on_card]).max() < MOTION_TOLERANCE_PIXELS
    # the wall did not move, nor the camera: exactly none
    assert not gbuffer["motion"][~on_card].any()
    # the card has no motion once it rests
    renderer.render_frame()
    assert not renderer.gbuffer()["motion"].any()


def _lengths(renderer: Renderer) -> np.ndarray:
    return renderer._temporal.records()["length"].reshape(SIZE, SIZE)


@pytest.mark.parametrize(**KINDS)
def test_a_sliding_card_keeps_its_history_and_the_wall_it_uncovers_starts_again(instanced):
    scene = card_scene(card=GREY, instanced=instanced)
    renderer = Renderer(scene, SIZE, SIZE)
    for _ in range(FRAMES_AT_REST):
        renderer.render_frame(pinhole(0.0))
    card_object(scene).transform = card_move((SLIDE_PIXELS, 0.0))
    renderer.render_frame()
    _, was_card = centre_hits(pinhole(0.0))
    _, is_card = centre_hits(pinhole(0.0), card=card_move((SLIDE_PIXELS, 0.0)))
    uncovered = was_card & ~is_card
    assert uncovered.sum() == SLIDE_PIXELS * (CARD_ROWS[1] - CARD_ROWS[0])
    # the wall the card now covers took the card's history along its motion, the wall elsewhere its own
    np.testing.assert_array_equal(_lengths(renderer), np.where(uncovered, 1.0, FRAMES_AT_REST + 1.0))


def _near(mask: np.ndarray, pixels: int) -> np.ndarray:
    """`mask` grown by `pixels` in every direction (a square)."""
    grown = mask.copy()
    for dy in range(-pixels, pixels + 1):
        for dx in range(-pixels, pixels + 1):
            shifted = np.zeros_like(mask)
            shifted[max(dy, 0) : SIZE + min(dy, 0), max(dx, 0) : SIZE + min(dx, 0)] = mask[
                max(-dy, 0) : SIZE + min(-dy, 0), max(-dx, 0) : SIZE + min(-dx, 0)
            ]
            grown |= shifted
    return grown


def test_a_sliding_card_leaves_no_colour_on_the_wall_behind_it():
    # max_depth 1: the white wall shows the grey sky alone, its red and green equal in every
    # sample, so any red on it came from the red lamp's history (demodulated by its colour clamped
    # to 1, the lamp's own light is still red). Two things keep it off: the uncovered wall's taps
    # fail the surface and depth tests, and the clamp to this frame's (grey) neighbourhood; breaking
    # both fails this test.
    scene = card_scene(card=Emitter("red lamp", color=(1.0, 0.1, 0.1), emittance=2.0))
    renderer = Renderer(scene, SIZE, SIZE, max_depth=1)
    renderer.render_frame(pinhole(0.0))
    _, covered = centre_hits(pinhole(0.0))
    for step in range(1, 5):
        move = card_move((2.0 * step, 0.0))
        card_object(scene).transform = move
        image = renderer.render_frame()
        _, on_card = centre_hits(pinhole(0.0), card=move)
        # the card's pixels and those whose neighbourhood clamp sees them
        away = ~_near(on_card, 2)
        covered |= on_card
        red = image[..., 0] - image[..., 1]
        assert not red[away].any(), f"frame {step}: the card's colour left on {np.count_nonzero(red[away])} pixels"
    # the wall the card had covered and left over a frame ago: six columns of it
    assert (covered & away).sum() == 6 * (CARD_ROWS[1] - CARD_ROWS[0])


def test_object_motions_exist_only_for_frames_and_upload_only_what_moved():
    scene = card_scene()
    renderer = Renderer(scene, SIZE, SIZE)
    renderer.render(1)
    assert not {OBJECT_MOTIONS, TRIANGLE_OBJECTS} & set(renderer.gpu_scene_bytes)
    renderer.render_frame()
    assert {OBJECT_MOTIONS, TRIANGLE_OBJECTS} <= set(renderer.gpu_scene_bytes)
    assert OBJECT_MOTIONS not in renderer.update()
    card_object(scene).transform = card_move((1.0, 0.0))
    # the card's record alone
    assert renderer.update()[OBJECT_MOTIONS].bytes == OBJECT_MOTION.size
    assert OBJECT_MOTIONS not in renderer.update()
