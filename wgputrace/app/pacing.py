"""Frame pacing: how much of a frame the tracing gets, how coarse the picture is while the camera
moves, and when the camera counts as resting so that the full resolution starts. While moving the
viewer traces one sample per pixel at the largest reduced size that fits the budget; resting, as
many samples (or rows of one) at full size as fit it."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

TARGET_FPS = 20.0
# Part of a frame kept for resolving, filtering, presenting and events, until measured.
INITIAL_OVERHEAD_SECONDS = 0.01
# Tracing gets at least this much of every frame, however slow presenting is.
MIN_TRACE_SECONDS = 0.005
# The camera counts as resting once it has not changed for this long.
REST_SECONDS = 0.25
# While moving the traced image is at least 1/MAX_PREVIEW_SCALE of the window in each direction.
MAX_PREVIEW_SCALE = 16
# Before the first frame has measured the adapter, the preview starts this coarse.
UNMEASURED_PREVIEW_SCALE = 8
# The fps shown and the per-frame cost besides tracing follow each frame by this fraction
# (smoothing over about ten frames).
FRAME_SMOOTHING = 0.1
# `frames` keeps at most this many records (a long session would otherwise grow it without end).
FRAME_LOG_LIMIT = 100_000


@dataclass
class FrameRecord:
    """One presented frame, for benchmarks and tests."""

    seconds: float  # wall time since the previous frame ended
    trace_seconds: float
    traced_size: tuple[int, int]
    samples_per_pixel: float
    moving: bool


class FramePacing:
    """The trace budget (the frame time less the measured cost of everything else), the preview size
    that fits it, whether the camera is moving and when it has rested, and the log of frames."""

    def __init__(self, target_fps: float) -> None:
        self.target_fps = target_fps
        self.moving = False
        self.frames: list[FrameRecord] = []
        self._overhead = INITIAL_OVERHEAD_SECONDS
        self._frame_seconds: float | None = None
        self._last_frame = time.perf_counter()
        self._last_change = 0.0
        self._turned = False

    @property
    def fps(self) -> float:
        return 0.0 if not self._frame_seconds else 1.0 / self._frame_seconds

    def trace_budget(self) -> float:
        return max(1.0 / self.target_fps - self._overhead, MIN_TRACE_SECONDS)

    def preview_size(self, banded) -> tuple[int, int]:
        """The largest reduced size of `banded`'s picture whose one sample per pixel fits the budget."""
        width, height = banded.full_size
        seconds_per_sample = banded.seconds_per_sample
        if seconds_per_sample is None:
            scale = UNMEASURED_PREVIEW_SCALE
        else:
            needed = width * height * seconds_per_sample / self.trace_budget()
            scale = min(max(math.ceil(math.sqrt(needed)), 2), MAX_PREVIEW_SCALE)
        return max(width // scale, 1), max(height // scale, 1)

    def camera_turned(self) -> None:
        """The camera was turned, reset or framed: the next frame restarts as moving."""
        self._turned = True

    def camera_moved(self, controller, now: float) -> bool:
        """Whether the camera moved since the last frame: by the keys held (FlyCamera.move) or turned."""
        moved = controller.move(now) or self._turned
        self._turned = False
        return moved

    def rested(self, now: float) -> bool:
        """Whether the moving camera has now been still for REST_SECONDS: time for the full size."""
        return self.moving and now - self._last_change >= REST_SECONDS

    def restarted(self, now: float, *, moving: bool) -> None:
        self.moving = moving
        if moving:
            self._last_change = now

    def frame_done(self, start: float, end: float, trace_seconds: float) -> float:
        """Measure a frame that ran from `start` to `end`; the seconds since the previous one ended."""
        self._overhead += FRAME_SMOOTHING * ((end - start - trace_seconds) - self._overhead)
        seconds = end - self._last_frame
        self._frame_seconds = (
            seconds
            if self._frame_seconds is None
            else self._frame_seconds + FRAME_SMOOTHING * (seconds - self._frame_seconds)
        )
        self._last_frame = end
        return seconds

    def record(self, frame: FrameRecord) -> None:
        self.frames.append(frame)
        if len(self.frames) > FRAME_LOG_LIMIT:
            del self.frames[: FRAME_LOG_LIMIT // 2]
