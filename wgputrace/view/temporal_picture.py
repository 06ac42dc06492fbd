"""The viewer's moving picture (its default `--preview temporal`): each frame a
`Renderer.render_frame` within the frame's budget, every pixel keeping its samples while the camera
moves, shown as one of FRAME_VIEWS (key V, `ViewSettings.frame_view`): the variance-guided
filter's picture by default, or a debug view of how it was made. The picture is uploaded into a
texture the present pass shows as it shows the resolved image."""

from __future__ import annotations

import time
from enum import Enum

import numpy as np

from ..gpu.graphics import image_texture, write_image
from ..render.renderer import Renderer
from ..render.temporal_accumulation import MOVING_HISTORY_FRAMES
from ..scene import Sensor
from .layout import IMAGE_FORMAT

# The motion view: red for motion to the right, green for motion down, at full strength from this
# many pixels a frame (a camera gliding at the viewer's speed moves a few pixels a frame).
MOTION_FULL_PIXELS = 4.0


class FrameView(Enum):
    """What the moving picture shows; the value is the overlay's name for it."""

    RAW = "raw frame"  # this frame's samples alone
    ACCUMULATION = "accumulation"  # the history's mean
    FILTERED = "SVGF filtered"  # the history through the variance-guided filter
    MOTION = "motion vectors"
    HISTORY = "history length"  # black: history rejected; white: MOVING_HISTORY_FRAMES frames or more

    @property
    def radiance(self) -> bool:
        """Whether it shows radiance (exposure and tone curve apply) rather than data."""
        return self not in (FrameView.MOTION, FrameView.HISTORY)


# The order key V steps through them.
FRAME_VIEWS = (FrameView.RAW, FrameView.ACCUMULATION, FrameView.FILTERED, FrameView.MOTION, FrameView.HISTORY)
DEFAULT_FRAME_VIEW = FrameView.FILTERED


def next_frame_view(view: FrameView) -> FrameView:
    """The view after `view` in FRAME_VIEWS (key V), the first after the last."""
    return FRAME_VIEWS[(FRAME_VIEWS.index(view) + 1) % len(FRAME_VIEWS)]


def motion_colors(motion: np.ndarray, hit: np.ndarray) -> np.ndarray:
    """The motion view of G-buffer motion vectors (h, w, 2) in pixels: grey (0.5) for none, red and
    green up or down with x and y, black where the pixel saw nothing (`hit` false)."""
    colors = np.full((*motion.shape[:2], 3), 0.5, np.float32)
    colors[..., :2] += 0.5 * np.clip(motion / MOTION_FULL_PIXELS, -1.0, 1.0)
    return np.where(hit[..., None], colors, 0.0).astype(np.float32)


def history_greys(length: np.ndarray, samples_per_frame: int) -> np.ndarray:
    """The history-length view of lengths (h, w) in samples: the frames they hold over
    MOVING_HISTORY_FRAMES, as grey (0: just rejected, 1: the moving cap or more)."""
    frames = length / max(samples_per_frame, 1)
    grey = np.clip(frames / MOVING_HISTORY_FRAMES, 0.0, 1.0).astype(np.float32)
    return np.repeat(grey[..., None], 3, axis=-1)


class TemporalPicture:
    """The moving picture of `renderer` (at its full size) and the texture showing it."""

    def __init__(self, renderer: Renderer) -> None:
        self.renderer = renderer
        self.texture = image_texture(renderer.context, "moving picture", renderer.width, renderer.height, IMAGE_FORMAT)
        self.samples_per_pixel = 0  # the last frame's
        self.frames = 0  # frames rendered

    @property
    def size(self) -> tuple[int, int]:
        return self.renderer.width, self.renderer.height

    def frame(self, camera: Sensor, budget: float, view: FrameView = DEFAULT_FRAME_VIEW) -> np.ndarray:
        """Render a frame through `camera` with `budget` seconds of tracing (at least one sample per
        pixel) and upload it as `view` shows it; returns that picture, float32 (height, width, 3)."""
        renderer = self.renderer
        image = renderer.render_frame(camera, budget=budget, filtered=view == FrameView.FILTERED)
        self.samples_per_pixel = renderer.stats.samples_per_pixel
        self.frames += 1
        if view == FrameView.RAW:
            image = renderer.image()
        elif view == FrameView.MOTION:
            gbuffer = renderer.gbuffer()
            image = motion_colors(gbuffer["motion"], gbuffer["depth"] > 0.0)
        elif view == FrameView.HISTORY:
            image = history_greys(renderer.history_length(), self.samples_per_pixel)
        write_image(renderer.context, self.texture, image)
        return image

    def advance(self, camera: Sensor, budget: float, view: FrameView) -> float:
        """A `frame`, for the viewer: the seconds it took."""
        start = time.perf_counter()
        self.frame(camera, budget, view)
        return time.perf_counter() - start
