"""The viewer's moving picture (its default `--preview temporal`): each frame a
`Renderer.render_frame` within the frame's budget, every pixel keeping its samples while the camera
moves, shown as one of FRAME_VIEWS (key V, `ViewSettings.frame_view`): the variance-guided
filter's picture by default, or a debug view of how it was made. Where tracing every pixel does
not fit the budget, a frame traces one pixel of every f x f block (`render_frame(upscale=f)`), f
chosen from each factor's measured cost (`choose_upscale`). The picture is uploaded into a texture
the present pass shows as it shows the resolved image."""

from __future__ import annotations

import time
from enum import Enum

import numpy as np

from ..gpu.graphics import image_texture, write_image
from ..render.renderer import Renderer
from ..render.temporal_accumulation import MOVING_HISTORY_FRAMES
from ..scene import Sensor
from .layout import IMAGE_FORMAT
from .upscale_choice import FrameCost, choose_upscale

# The motion view: red for motion to the right, green for motion down, at full strength from this
# many pixels a frame (a camera gliding at the viewer's speed moves a few pixels a frame).
MOTION_FULL_PIXELS = 4.0


class FrameView(Enum):
    """What the moving picture shows; the value is the overlay's name for it."""

    RAW = "raw frame"  # this frame's samples alone
    ACCUMULATION = "accumulation"  # the history's mean
    FILTERED = "SVGF filtered"  # the history through the variance-guided filter (and upsampled, TAA)
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


def history_greys(length: np.ndarray, samples_per_frame: int, upscale: int = 1) -> np.ndarray:
    """The history-length view of lengths (h, w) in samples: the frames' worth they hold over
    MOVING_HISTORY_FRAMES, as grey (0: just rejected, 1: the moving cap or more). Upscaled, a
    pixel takes its samples once every upscale x upscale frames."""
    frames = length * upscale**2 / max(samples_per_frame, 1)
    grey = np.clip(frames / MOVING_HISTORY_FRAMES, 0.0, 1.0).astype(np.float32)
    return np.repeat(grey[..., None], 3, axis=-1)


def traced_blocks(image: np.ndarray, factor: int, offset: tuple[int, int]) -> np.ndarray:
    """`image` (h, w, ...) as a frame upscaled by `factor` traced it: the pixel at `offset` (x, y)
    of every factor x factor block fills its block, as the reset preview shows its reduced image;
    a block cut by the image's edge without its traced pixel takes the previous block's."""
    if factor == 1:
        return image

    def traced(count: int, start: int) -> np.ndarray:
        pixels = np.arange(count) // factor * factor + start
        return np.where(pixels < count, pixels, pixels - factor)

    return image[traced(image.shape[0], offset[1])[:, None], traced(image.shape[1], offset[0])[None, :]]


class TemporalPicture:
    """The moving picture of `renderer` (at its full size) and the texture showing it."""

    def __init__(self, renderer: Renderer) -> None:
        self.renderer = renderer
        self.texture = image_texture(renderer.context, "moving picture", renderer.width, renderer.height, IMAGE_FORMAT)
        self.samples_per_pixel = 0  # the last frame's
        self.frames = 0  # frames rendered
        self.upscale: int | None = None  # the last frame's factor
        self._frames_at_factor = 0  # frames in a row at it
        # each factor's cost of one frame, measured (choose_upscale)
        self.costs: dict[int, FrameCost] = {}

    @property
    def size(self) -> tuple[int, int]:
        return self.renderer.width, self.renderer.height

    @property
    def traced_size(self) -> tuple[int, int]:
        """The pixels the last frame traced, as an image: one per block of its upscale factor."""
        factor = self.upscale or 1
        return -(-self.renderer.width // factor), -(-self.renderer.height // factor)

    def frame(
        self, camera: Sensor, budget: float, view: FrameView = DEFAULT_FRAME_VIEW, upscale: int | None = None
    ) -> np.ndarray:
        """Render a frame through `camera` with `budget` seconds of tracing (at least one sample per
        traced pixel) and upload it as `view` shows it; returns that picture, float32 (height,
        width, 3). `upscale`: the factor (1 or one of UPSCALE_FACTORS), or None: the one
        `choose_upscale` takes for the budget. Changing the factor starts the history again."""
        renderer = self.renderer
        if upscale is None:
            factor = choose_upscale(self.costs, budget, self.size, self.upscale, self._frames_at_factor)
        else:
            factor = upscale
        start = time.perf_counter()
        # the tracing gets what the rest of the frame, measured at this factor, leaves of the
        # budget; one sample until it is measured or where nothing is left
        cost = self.costs.get(factor)
        tracing = {"budget": budget - cost.rest} if cost is not None and budget > cost.rest else {"spp": 1}
        image = renderer.render_frame(camera, filtered=view == FrameView.FILTERED, upscale=factor, **tracing)
        stats = renderer.stats
        self.samples_per_pixel = stats.samples_per_pixel
        self.frames += 1
        if view in (FrameView.RAW, FrameView.MOTION):
            subset = renderer.traced_subset()
            if view == FrameView.RAW:
                image = traced_blocks(renderer.image(), *subset)
            else:
                gbuffer = renderer.gbuffer()
                hit = gbuffer["depth"] > 0.0
                image = traced_blocks(motion_colors(gbuffer["motion"], hit), *subset)
        elif view == FrameView.HISTORY:
            image = history_greys(renderer.history_length(), self.samples_per_pixel, factor)
        write_image(renderer.context, self.texture, image)
        # the first frame at a factor starts its history (and may compile its kernel): not its cost
        if factor == self.upscale:
            trace = stats.render_seconds / max(stats.samples_per_pixel, 1)
            measured = FrameCost(trace, time.perf_counter() - start - stats.render_seconds)
            self.costs[factor] = measured if cost is None else cost.smoothed(measured)
        self._frames_at_factor = self._frames_at_factor + 1 if factor == self.upscale else 1
        self.upscale = factor
        return image

    def advance(self, camera: Sensor, budget: float, view: FrameView) -> float:
        """A `frame`, for the viewer (its factor chosen from the budget): the seconds it took."""
        start = time.perf_counter()
        self.frame(camera, budget, view)
        return time.perf_counter() - start
