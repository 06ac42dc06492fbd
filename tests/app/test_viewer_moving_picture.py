"""The viewer while the camera moves (keys held, as rendercanvas delivers them; offscreen canvas):
the moving picture keeps every pixel's samples across frames and shows them through the
variance-guided filter, so a screenshot taken in motion is the scene at full resolution (not
black, not blocky) and closer to a converged render than the reset preview's (`--preview reset`);
key V steps through the debug views (raw frame, accumulation, filtered, motion vectors, history
length), whose name the overlay shows. With `--integrator restir` the moving picture's paths take
their first vertex's light from resampled candidates."""

from __future__ import annotations

import time

import numpy as np
import pytest
from PIL import Image

from wgputrace import Renderer, load_image
from wgputrace.app.pacing import TARGET_FPS
from wgputrace.loaders import load_scene
from wgputrace.testing.image_statistics import displayed_mse, equal_neighbour_fraction
from wgputrace.testing.offscreen_viewer import SIZE, frames, offscreen_viewer
from wgputrace.view.reset_preview import scaled_up
from wgputrace.view.temporal_picture import FRAME_VIEWS, FrameView
from wgputrace.view.upscale_choice import FIRST_FACTOR

pytestmark = pytest.mark.gpu

SCENE = "cornell"
# W held for this many frames, each after a short pause (the camera moves by the time held)
MOVING_FRAMES = 12
FRAME_PAUSE_SECONDS = 0.01
REFERENCE_SPP = 64
REFERENCE_SEED = 99
# The reset preview traces at most half the window's size each way, so at least half of the pairs
# of neighbouring pixels it shows are copies of one traced pixel (a little less: blocks at the
# edges); at full resolution few pairs are equal.
BLOCKY_EQUAL_PAIRS = 0.45
FULL_RESOLUTION_EQUAL_PAIRS = 0.25
# The picture is the lit box, not black: its mean 8-bit value is well above this.
NOT_BLACK_MEAN = 20
# Target frame rates: one whose budget fits a full frame of SIZE on lavapipe (a frame and its
# filter take tens of milliseconds), and one whose budget (MIN_TRACE_SECONDS) no frame fits.
GENEROUS_FPS = 4.0
HOPELESS_FPS = 1000.0


def _key(viewer, kind: str, key: str) -> None:
    viewer.input.on_event({"event_type": kind, "key": key, "modifiers": [], "time_stamp": time.perf_counter()})


def _moving(viewer, count: int = MOVING_FRAMES) -> None:
    """Draw `count` frames with W held, then let it go: the viewer moves on for the time it was held
    at its next frame, and rests REST_SECONDS after that."""
    _key(viewer, "key_down", "w")
    for _ in range(count):
        time.sleep(FRAME_PAUSE_SECONDS)
        frames(viewer, 1)
    _key(viewer, "key_up", "w")


def _screenshot(viewer) -> tuple[np.ndarray, np.ndarray]:
    """(the PNG's pixels, the EXR's linear image) of what the viewer shows now."""
    png, exr = viewer.screenshot()
    return np.asarray(Image.open(png).convert("RGB")), load_image(exr)


def _converged(camera) -> np.ndarray:
    scene = load_scene(SCENE)
    scene.camera = camera
    renderer = Renderer(scene, *SIZE, seed=REFERENCE_SEED)
    renderer.render(REFERENCE_SPP)
    return renderer.image()


@pytest.fixture(scope="module")
def moved(gpu_context, tmp_path_factory):
    """Each preview's viewer after MOVING_FRAMES frames of W: (viewer, PNG pixels, EXR) by preview;
    "upscaled": the moving picture with a budget no full frame fits; "restir": the moving picture
    traced by restir."""
    shots = {}
    previews = (
        ("temporal", {"target_fps": GENEROUS_FPS}),
        ("reset", {"filter": True}),
        ("upscaled", {"target_fps": HOPELESS_FPS}),
        ("restir", {"target_fps": GENEROUS_FPS, "integrator": "restir"}),
    )
    for name, options in previews:
        preview = "reset" if name == "reset" else "temporal"
        viewer = offscreen_viewer(SCENE, tmp_path_factory.mktemp(name), preview=preview, **options)
        viewer.input.press("Tab")  # no overlay over the picture
        frames(viewer, 1)
        # the same way in as at the default frame rate, whose frames are shorter
        viewer.controller.speed *= min(options.get("target_fps", TARGET_FPS) / TARGET_FPS, 1.0)
        _moving(viewer)
        assert viewer.pacing.moving
        shots[name] = (viewer, *_screenshot(viewer))
    return shots


def test_a_moving_camera_shows_the_scene_at_full_resolution_closer_than_the_reset_preview(moved):
    viewer, pixels, linear = moved["temporal"]
    assert viewer.shown_label() == FrameView.FILTERED.value
    assert viewer.frames[-1].traced_size == SIZE and viewer.frames[-1].moving
    # the first moving frame starts upsampled, then the budget fits every pixel
    assert viewer.frames[1].upscale == FIRST_FACTOR and viewer.frames[-1].upscale == 1
    assert pixels.mean() > NOT_BLACK_MEAN, "the moving picture is black"
    reset_viewer, reset_pixels, reset_linear = moved["reset"]
    assert equal_neighbour_fraction(reset_pixels) > BLOCKY_EQUAL_PAIRS, "the reset preview was not blocky"
    assert equal_neighbour_fraction(pixels) < FULL_RESOLUTION_EQUAL_PAIRS, "the moving picture is blocky"
    errors = {
        name: displayed_mse(scaled_up(image, SIZE), _converged(shot_viewer.controller.camera()))
        for name, shot_viewer, image in (("temporal", viewer, linear), ("reset", reset_viewer, reset_linear))
    }
    assert errors["temporal"] < errors["reset"], f"displayed MSE against a converged render: {errors}"


def test_a_budget_no_full_frame_fits_upsamples_the_moving_picture_and_it_is_not_blocky(moved):
    viewer, pixels, linear = moved["upscaled"]
    moving = [frame for frame in viewer.frames if frame.moving]
    assert moving and all(frame.upscale > 1 for frame in moving), [frame.upscale for frame in moving]
    last = moving[-1]
    assert last.traced_size == (-(-SIZE[0] // last.upscale), -(-SIZE[1] // last.upscale))
    assert any(f"upscale {last.upscale}" in line for line in viewer.info_lines())
    assert linear.shape == (SIZE[1], SIZE[0], 3) and np.isfinite(linear).all()
    assert pixels.mean() > NOT_BLACK_MEAN, "the upsampled moving picture is black"
    assert equal_neighbour_fraction(pixels) < FULL_RESOLUTION_EQUAL_PAIRS, "the upsampled moving picture is blocky"


def test_key_v_steps_through_the_debug_views_and_the_overlay_names_them(moved):
    viewer, filtered_pixels, filtered = moved["temporal"]
    shown = {}
    start = FRAME_VIEWS.index(FrameView.FILTERED) + 1
    for expected in FRAME_VIEWS[start:] + FRAME_VIEWS[:start]:
        _key(viewer, "key_down", "v")
        assert viewer.overlay.status == f"moving picture: {expected.value}"
        _moving(viewer, 2)
        assert viewer.shown_label() == expected.value
        assert any(f"view radiance: {expected.value}" in line for line in viewer.info_lines())
        shown[expected] = _screenshot(viewer)[1]
    motion = shown[FrameView.MOTION]
    # moving forward the picture spreads from its centre: points on the left came from the right
    # (red above the neutral 0.5), points on the right from the left
    middle = SIZE[0] // 2
    assert motion[:, : middle - 4, 0].mean() > 0.5 > motion[:, middle + 4 :, 0].mean()
    history = shown[FrameView.HISTORY]
    assert np.array_equal(history[..., 0], history[..., 1]), "the history length is shown in grey"
    assert history.max() > 0.0
    # one frame's samples are noisier than their history's mean, and that than the filtered picture
    roughness = {view: np.abs(np.diff(shown[view], axis=1)).mean() for view in FRAME_VIEWS[:3]}
    assert roughness[FrameView.RAW] > roughness[FrameView.ACCUMULATION] > roughness[FrameView.FILTERED], roughness


def test_key_v_with_the_reset_preview_says_why_there_is_nothing_to_show(moved):
    viewer = moved["reset"][0]
    _key(viewer, "key_down", "v")
    assert viewer.overlay.status == "no moving-picture views: --preview reset"


def test_the_moving_picture_traced_by_restir_is_the_scene_closer_than_the_reset_preview(moved):
    viewer, pixels, linear = moved["restir"]
    renderer = viewer.view.renderer
    assert renderer.integrator.name == "restir"
    assert any("integrator restir" in line for line in viewer.info_lines())
    assert viewer.frames[-1].moving and viewer.frames[-1].upscale == 1
    assert pixels.mean() > NOT_BLACK_MEAN and np.isfinite(linear).all()
    reset_viewer, _, reset_linear = moved["reset"]
    errors = {
        name: displayed_mse(scaled_up(image, SIZE), _converged(shot_viewer.controller.camera()))
        for name, shot_viewer, image in (("restir", viewer, linear), ("reset", reset_viewer, reset_linear))
    }
    assert errors["restir"] < errors["reset"], f"displayed MSE against a converged render: {errors}"
