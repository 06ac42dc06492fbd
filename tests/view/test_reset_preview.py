"""The reset preview headless (`ResetPreview`, the viewer's `--preview reset`): each camera change
starts the samples again at the largest reduced size whose pass fits the budget, and the picture
is that size scaled up to the window by the present pass's nearest pixel; frames of an unchanged
camera add passes. `preview_size` and `scaled_up` against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Renderer, default_scene
from wgputrace.view.reset_preview import (
    MAX_PREVIEW_SCALE,
    UNMEASURED_PREVIEW_SCALE,
    ResetPreview,
    preview_size,
    scaled_up,
)

WIDTH, HEIGHT = 64, 48
# far below one pass of the window on any adapter: the coarsest preview
TINY_BUDGET = 1e-9


def test_preview_sizes():
    assert preview_size((640, 480), None, 0.05) == (640 // UNMEASURED_PREVIEW_SCALE, 480 // UNMEASURED_PREVIEW_SCALE)
    # 307,200 samples at 1.6e-6 s need 0.49 s: 9.8 times the budget, a scale of ceil(sqrt(9.8)) = 4
    assert preview_size((640, 480), 1.6e-6, 0.05) == (160, 120)
    assert preview_size((640, 480), 1e-12, 0.05) == (320, 240), "never the full size"
    assert preview_size((640, 480), 1.0, 0.05) == (640 // MAX_PREVIEW_SCALE, 480 // MAX_PREVIEW_SCALE)


def test_scaled_up_is_the_present_pass_nearest_pixel():
    image = np.arange(6, dtype=np.float32).reshape(2, 3, 1)
    np.testing.assert_array_equal(scaled_up(image, (6, 4))[..., 0], np.repeat(np.repeat(image[..., 0], 2, 0), 2, 1))


@pytest.mark.gpu
def test_a_camera_change_starts_again_at_the_reduced_size():
    preview = ResetPreview(Renderer(default_scene(), WIDTH, HEIGHT))
    camera = default_scene().camera
    first = preview.frame(camera, TINY_BUDGET)
    banded = preview.banded
    reduced = banded.size
    assert first.shape == (HEIGHT, WIDTH, 3) and np.isfinite(first).all() and first.mean() > 0.0
    assert reduced[0] <= WIDTH // 2 and reduced[1] <= HEIGHT // 2
    np.testing.assert_array_equal(first, scaled_up(preview.display.read_image(), (WIDTH, HEIGHT)))
    preview.frame(camera, TINY_BUDGET)
    assert banded.samples_per_pixel == 2, "the same camera adds a pass"
    preview.frame(Camera(position=(0.05, 0.31, -1.2), forward=(0, 0, 1), vfov_degrees=60), TINY_BUDGET)
    assert banded.samples_per_pixel == 1, "a new camera starts again"
