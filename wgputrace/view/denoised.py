"""The viewer's Open Image Denoise picture (key D): the resting camera's samples denoised in a
background thread, and the texture the result is presented from (the same present pass as the
resolved image: exposure, sRGB, overlay).

A denoise reads the mean and the guides (Renderer.image() and guides(), the means of the banded
renderer's samples) at the full size between passes, when the schedule says it is due; OIDN runs
in a worker thread (pyoidn calls into OIDN through cffi, which releases the GIL, so frames go on);
a finished result of the current camera's samples is uploaded and shown until the camera moves or
a newer one is ready. OIDN takes the machine's cores while it runs, so the schedule spaces the
runs out: see DenoiseSchedule.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from ..denoise import denoise
from ..gpu.graphics import image_texture, write_image
from .banded import BandedRenderer
from .layout import IMAGE_FORMAT

# OIDN's mode for the viewer: on two CPU cores at 640x480 with guides, "balanced" took 0.65 s,
# "fast" 0.58 s and "high" 1.45 s (high is for final frames: `wgputrace render --denoise`).
QUALITY = "balanced"
# A denoise is due once the samples per pixel have grown by this factor since the last one began
# (the first at one sample per pixel): the noise OIDN removes falls as 1/sqrt(spp), so runs at
# doubling counts each show a picture visibly better than the one before.
SAMPLE_GROWTH = 2.0
# ... and no sooner after the last one ended than this many times the seconds it took: OIDN then
# has at most 1 / (1 + IDLE_FACTOR) of the time, and path tracing keeps the rest.
IDLE_FACTOR = 3.0

# One worker for the process: OIDN serialises its work on a device anyway, and a view made again
# (a resize, a reloaded scene) queues behind a denoise of the old one rather than beside it.
_worker = ThreadPoolExecutor(max_workers=1, thread_name_prefix="wgputrace-denoise")


class DenoiseFailure(RuntimeError):
    """OIDN refused or failed on the viewer's image (the message says why)."""


@dataclass
class DenoiseSchedule:
    """When the next denoise may start: at 1 spp after a camera change, then each time the samples
    have grown by SAMPLE_GROWTH, and never sooner than IDLE_FACTOR times the last one's duration
    after it ended (that holds across camera changes: the cores are as busy either way)."""

    next_samples: int = 1
    not_before: float = 0.0

    def due(self, samples: int, now: float) -> bool:
        return samples >= self.next_samples and now >= self.not_before

    def started(self, samples: int) -> None:
        self.next_samples = math.ceil(samples * SAMPLE_GROWTH)

    def finished(self, seconds: float, now: float) -> None:
        self.not_before = now + IDLE_FACTOR * seconds

    def camera_changed(self) -> None:
        self.next_samples = 1


@dataclass
class _Job:
    """A denoise in the worker: of which camera's samples, how many, and its result to come."""

    generation: int
    samples: int
    future: Future = field(repr=False)


def _timed_denoise(image: np.ndarray, guides: dict[str, np.ndarray]) -> tuple[np.ndarray, float]:
    start = time.perf_counter()
    denoised = denoise(image, **guides, quality=QUALITY)
    return denoised, time.perf_counter() - start


class DenoisedPicture:
    """OIDN's picture of a BandedRenderer's samples, made in the background; the renderer must
    have its guides on (Renderer.guides_enabled)."""

    def __init__(self, banded: BandedRenderer, device_name: str) -> None:
        self.banded = banded
        self.context = banded.context
        self.device_name = device_name  # OIDN's device ("CPU", "CUDA"): the overlay names it
        width, height = banded.full_size
        self.texture = image_texture(self.context, "denoised image", width, height, IMAGE_FORMAT)
        self.shown_samples: int | None = None  # samples per pixel of the picture in `texture`, if current
        self.last_seconds: float | None = None  # how long the last denoise took
        self.schedule = DenoiseSchedule()
        self._generation = 0  # counts camera changes: a result of an older one is not shown
        self._job: _Job | None = None

    @property
    def shown(self) -> bool:
        """Whether `texture` holds a denoised picture of the current camera's samples."""
        return self.shown_samples is not None

    def camera_changed(self) -> None:
        """The picture is stale (call after BandedRenderer.restart); a denoise under way is dropped when it ends."""
        self._generation += 1
        self.shown_samples = None
        self.schedule.camera_changed()

    def update(self, now: float, *, start: bool = True) -> None:
        """Take a finished denoise (shown if of the current camera's samples); start the next where
        it is due and `start` allows (not while the viewer's moving picture holds the renderer's
        buffers). Raises DenoiseFailure where OIDN failed."""
        self._collect(now)
        banded = self.banded
        resting_between_passes = not banded.reduced and banded.rows_done == 0
        due = start and resting_between_passes and self.schedule.due(banded.samples_per_pixel, now)
        if self._job is None and due:
            self._start()

    def _start(self) -> None:
        renderer = self.banded.renderer
        samples = self.banded.samples_per_pixel
        future = _worker.submit(_timed_denoise, renderer.image(), renderer.guides())
        self._job = _Job(self._generation, samples, future)
        self.schedule.started(samples)

    def _collect(self, now: float) -> None:
        job = self._job
        if job is None or not job.future.done():
            return
        self._job = None
        try:
            denoised, seconds = job.future.result()
        except (ValueError, RuntimeError) as error:  # a refused input, or OIDN's own failure
            raise DenoiseFailure(f"OIDN ({self.device_name}) failed on the viewer's image: {error}") from error
        self.last_seconds = seconds
        self.schedule.finished(seconds, now)
        if job.generation == self._generation:
            write_image(self.context, self.texture, denoised)
            self.shown_samples = job.samples

    def label(self) -> str:
        """What the overlay says is shown: "OIDN (CPU), 16 spp"."""
        return f"OIDN ({self.device_name}), {self.shown_samples} spp"
