"""The viewer in a real window on a virtual X display with a frame budget no full frame fits
(`--fps` far above what lavapipe reaches): while W is held, the moving picture traces one pixel
per block (upscale > 1), and each screenshot of it is the scene at full resolution, not black and
not the blocky preview."""

from __future__ import annotations

import time

import numpy as np
import pytest
from PIL import Image

from wgputrace.testing.image_statistics import equal_neighbour_fraction
from wgputrace.testing.running_app import START_SECONDS, RunningApp
from wgputrace.testing.xdriver import XDriver
from wgputrace.view.temporal_picture import FrameView

pytestmark = [pytest.mark.gpu, pytest.mark.slow]

WIDTH, HEIGHT = 128, 96
TITLE = "wgputrace - cornell"
# Its budget is MIN_TRACE_SECONDS: no frame of 128x96 with its filter fits on lavapipe.
HOPELESS_FPS = 1000
# Screenshots taken while W is held, this far apart: frames of the moving picture come in between.
SHOTS = 3
SHOT_SECONDS = 0.3
# As in test_window: the lit box is well above this mean 8-bit value, and at full resolution few
# neighbouring pixels are equal (the reset preview's blocks make half or more).
NOT_BLACK_MEAN = 20
FULL_RESOLUTION_EQUAL_PAIRS = 0.25


@pytest.fixture(scope="module")
def viewer(x_display, tmp_path_factory):
    folder = tmp_path_factory.mktemp("viewer")
    arguments = ["cornell", "--size", f"{WIDTH}x{HEIGHT}", "--fps", str(HOPELESS_FPS), "--screenshots", str(folder)]
    app = RunningApp(arguments, folder)
    driver = XDriver(x_display)
    try:
        app.wait_for("showing cornell", START_SECONDS)
        window = driver.find_window(TITLE, START_SECONDS)
        driver.pointer_to(window, WIDTH // 2, HEIGHT // 2)  # no window manager: the pointer gives focus
        yield app, driver
    finally:
        driver.close()
        app.stop()


def test_moving_with_a_budget_no_full_frame_fits_shows_the_upsampled_scene_not_blocks(gpu_context, viewer):
    app, driver = viewer
    driver.tap("Tab")  # no overlay over the picture
    driver.key_down("w")
    shots = []
    try:
        for _ in range(SHOTS):
            time.sleep(SHOT_SECONDS)
            driver.tap("p")
            shots.append(app.screenshot_line())
    finally:
        driver.key_up("w")
    positions = [shot.position[2] for shot in shots]
    assert positions == sorted(positions) and positions[0] < positions[-1], f"the camera did not move: {positions}"
    for shot in shots:
        assert shot.shown == FrameView.FILTERED.value and shot.size == (WIDTH, HEIGHT)
        assert shot.upscale > 1, f"{shot.png}: a frame of every pixel within {1 / HOPELESS_FPS} s"
        pixels = np.asarray(Image.open(shot.png).convert("RGB"))
        assert pixels.mean() > NOT_BLACK_MEAN, f"{shot.png}: the upsampled moving picture is black"
        blocky = equal_neighbour_fraction(pixels)
        assert blocky < FULL_RESOLUTION_EQUAL_PAIRS, f"{shot.png}: the upsampled moving picture is blocky ({blocky})"
