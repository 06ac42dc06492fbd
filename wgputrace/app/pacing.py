"""Frame pacing: how much of a frame the tracing gets, how coarse the reset preview is while the
camera moves, and when the camera counts as resting so that the full-size accumulation starts.
While moving the viewer traces a moving-picture frame within the budget (or, with the reset
preview, one sample per pixel at the largest reduced size that fits it); resting, as many samples
(or rows of one) at full size as fit it."""

from __future__ import annotations

import time
from dataclasses import dataclass

from ..view.reset_preview import preview_size

TARGET_FPS = 20.0
# Part of a frame kept for resolving, filtering, presenting and events, until measured.
INITIAL_OVERHEAD_SECONDS = 0.01
# Tracing gets at least this much of every frame, however slow presenting is.
MIN_TRACE_SECONDS = 0.005
# The camera counts as resting once it has not changed for this long.
REST_SECONDS = 0.25
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
    upscale: int = 1  # the moving picture's factor: one pixel of every upscale x upscale block traced


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
        return preview_size(banded.full_size, banded.seconds_per_sample, self.trace_budget())

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

    def frame_done(self, start: float, end: float, trace_seconds: float, setup_seconds: float = 0.0) -> float:
        """Measure a frame that ran from `start` to `end`; the seconds since the previous one ended.
        `setup_seconds`: what the frame spent once (a view made for a new scene or size, its kernels
        compiled), kept out of the cost per frame, which would otherwise starve the next frames' tracing."""
        self._overhead += FRAME_SMOOTHING * ((end - start - trace_seconds - setup_seconds) - self._overhead)
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
