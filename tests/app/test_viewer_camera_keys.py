"""The viewer's camera and tone keys on the offscreen canvas: T cycles the tone curve and +/- step
the exposure in half stops (a screenshot is `tonemap`'s picture of its own EXR), X measures the
exposure on the GPU, the aperture keys turn the pinhole into a thin lens and back, and a click
focuses the lens at the depth under the pointer."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from PIL import Image

from wgputrace import Camera, ThinLensCamera, load_image
from wgputrace.image_io import MIDDLE_GREY, linear_to_srgb, srgb8, tone_curve
from wgputrace.testing.offscreen_viewer import SIZE, frames, offscreen_viewer
from wgputrace.view.present import Tone

pytestmark = pytest.mark.gpu

# The 8-bit picture against float64 numpy: one code value
SRGB_CODES = 1
REST_SECONDS = 20.0
# A wall straight ahead of the camera at this distance, a lamp behind the camera lighting it.
WALL_DISTANCE = 3.0
WALL_SCENE = f"""import wgputrace as wt


def scene():
    wall = wt.make_plane((0, 0, {WALL_DISTANCE}), (-1.5707963, 0, 0), (40, 40), wt.Diffuse("wall"), "wall")
    lamp = wt.make_plane((0, 0, -1), (1.5707963, 0, 0), (4, 4), wt.Emitter("lamp"), "lamp")
    return wt.Scene([wall, lamp], wt.Camera((0, 0, 0), (0, 0, 1), (0, 1, 0), 40.0))
"""


def rested(viewer) -> None:
    """Draw frames until the camera rests and the full-size picture has a sample."""
    deadline = time.perf_counter() + REST_SECONDS
    while time.perf_counter() < deadline:
        viewer.canvas.draw()
        banded = viewer.view.banded
        if not viewer.pacing.moving and banded.size == banded.full_size and banded.samples_per_pixel >= 1:
            return
    raise AssertionError("the viewer did not rest")


def shown_as(linear: np.ndarray, tone: Tone, log_average: float | None = None) -> np.ndarray:
    scale = 2.0**tone.ev * (MIDDLE_GREY / math.exp(log_average) if tone.automatic else 1.0)
    return srgb8(linear_to_srgb(tone_curve(linear.astype(np.float64) * scale, tone.operator)))


def test_tone_keys_and_the_screenshot_is_the_curve_of_its_exr(gpu_context, tmp_path):
    viewer = offscreen_viewer("sunlit_spheres", tmp_path)
    rested(viewer)
    for key in ("t", "t", "-"):
        viewer.input.press(key)
    assert viewer.tone == Tone("agx", -0.5, False)
    viewer.input.press("Tab")  # no overlay over the picture
    frames(viewer, 1)
    png, exr = viewer.screenshot()
    pixels = np.asarray(Image.open(png).convert("RGB")).astype(int)
    assert np.abs(pixels - shown_as(load_image(exr), viewer.tone)).max() <= SRGB_CODES
    for _ in range(3):
        viewer.input.press("t")
    assert viewer.tone.operator == "pbr_neutral"


def test_auto_exposure_is_measured_on_the_gpu_and_shown(gpu_context, tmp_path):
    viewer = offscreen_viewer("sunlit_spheres", tmp_path)
    rested(viewer)
    viewer.input.press("x")
    viewer.input.press("Tab")
    frames(viewer, 2)
    assert viewer.tone.automatic
    png, exr = viewer.screenshot()
    log_average = viewer.device.presenter.measured_log_average()
    linear = load_image(exr)
    # the measurement follows the picture; a sample or two later it is still the picture's log average
    luminance = linear.reshape(-1, 3).astype(np.float64) @ [0.2126, 0.7152, 0.0722]
    assert log_average == pytest.approx(np.mean(np.log(np.maximum(luminance, 1e-4))), abs=0.05)
    pixels = np.asarray(Image.open(png).convert("RGB")).astype(int)
    assert np.abs(pixels - shown_as(linear, viewer.tone, log_average)).max() <= SRGB_CODES


def test_aperture_keys_and_a_click_focus_the_lens(gpu_context, tmp_path):
    path = tmp_path / "wall.py"
    path.write_text(WALL_SCENE)
    viewer = offscreen_viewer(str(path), tmp_path)
    rested(viewer)
    viewer.input.press(".")
    rested(viewer)
    assert isinstance(viewer.view.renderer.scene.camera, ThinLensCamera)
    assert "ThinLensCamera" in viewer.view.renderer.variant.label
    for event in ("pointer_down", "pointer_up"):
        viewer.input.on_event({"event_type": event, "button": 1, "x": SIZE[0] * 0.3, "y": SIZE[1] * 0.7})
    # the wall is perpendicular to the axis: the depth under any pixel is its distance along it
    assert viewer.controller.focus_distance == pytest.approx(WALL_DISTANCE, rel=1e-5)
    rested(viewer)
    assert viewer.view.renderer.scene.camera.focus_distance == pytest.approx(WALL_DISTANCE, rel=1e-5)
    viewer.input.press(",")
    rested(viewer)
    assert type(viewer.view.renderer.scene.camera) is Camera
    assert "ThinLensCamera" not in viewer.view.renderer.variant.label


def test_an_orthographic_view_has_no_lens_to_open(gpu_context, tmp_path):
    viewer = offscreen_viewer("orthographic_boxes", tmp_path)
    rested(viewer)
    viewer.input.press(".")
    for event in ("pointer_down", "pointer_up"):
        viewer.input.on_event({"event_type": event, "button": 1, "x": 10.0, "y": 10.0})
    assert "has no lens" in viewer.overlay.status
    assert viewer.controller.aperture_radius is None
