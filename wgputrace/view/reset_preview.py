"""The preview that starts again whenever the camera moves (the viewer's `--preview reset`, and
what it showed while moving before temporal accumulation): one sample per pixel at the largest
reduced size whose pass fits the frame's budget, through the a-trous filter (Display) where asked,
scaled up to the window as the present pass scales it (nearest pixel). `ResetPreview` runs it
headless, frame by frame, for comparisons (`python -m bench.realtime`)."""

from __future__ import annotations

import math

import numpy as np

from ..render.renderer import Renderer
from ..scene import Sensor
from .banded import BandedRenderer
from .display import Display, ViewSettings

# While moving the traced image is at least 1/MAX_PREVIEW_SCALE of the window in each direction.
MAX_PREVIEW_SCALE = 16
# Before the first frame has measured the adapter, the preview starts this coarse.
UNMEASURED_PREVIEW_SCALE = 8


def preview_size(full_size: tuple[int, int], seconds_per_sample: float | None, budget: float) -> tuple[int, int]:
    """The largest size, the full one divided by a whole scale from 2 to MAX_PREVIEW_SCALE, whose one
    sample per pixel fits `budget` seconds at `seconds_per_sample` (None: not measured yet)."""
    width, height = full_size
    if seconds_per_sample is None:
        scale = UNMEASURED_PREVIEW_SCALE
    else:
        needed = width * height * seconds_per_sample / budget
        scale = min(max(math.ceil(math.sqrt(needed)), 2), MAX_PREVIEW_SCALE)
    return max(width // scale, 1), max(height // scale, 1)


def scaled_up(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """`image` (h, w, c) at `size` (width, height) by the present pass's nearest pixel (present.wgsl:
    target pixel * image size / target size, in integers)."""
    rows = np.arange(size[1]) * image.shape[0] // size[1]
    columns = np.arange(size[0]) * image.shape[1] // size[0]
    return image[rows[:, None], columns[None, :]]


class ResetPreview:
    """Today's moving picture of `renderer`, headless: `frame(camera, budget)` starts the samples
    again at the preview size where the camera changed and adds the passes that fit the budget;
    `filtered`: through the viewer's a-trous filter at the weight it has at that many samples."""

    def __init__(self, renderer: Renderer, *, filtered: bool = True) -> None:
        self.banded = BandedRenderer(renderer)
        self.display = Display(self.banded)
        self.settings = ViewSettings(filter_enabled=filtered)
        self._camera: Sensor | None = None

    def frame(self, camera: Sensor, budget: float) -> np.ndarray:
        """One frame through `camera` with `budget` seconds of tracing (at least one pass): the
        picture the window shows, float32 (height, width, 3) at the renderer's full size."""
        banded = self.banded
        if camera != self._camera:
            banded.restart(camera, preview_size(banded.full_size, banded.seconds_per_sample, budget))
            self.display.camera_changed()
            self._camera = camera
        banded.advance(budget, whole_pass=True)
        self.display.render(self.settings)
        return scaled_up(self.display.read_image(), banded.full_size)
