"""Progressive rendering within a time budget: samples added a band of rows at a time, at the
full image size or a reduced one, into a Renderer's own buffers (the viewer's renderer).

A pass over the whole image adds one sample per pixel. When a pass takes longer than the budget,
each call renders the band of rows that fits and the next goes on below it; otherwise a call
renders as many whole passes as fit. A reduced size traces only the top-left width x height
pixels through a camera with the same field of view (the preview while the camera moves). Whole
passes count in the renderer's stats, so its image() and guides() are the means of these samples.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ..gpu.bindings import IMAGE_WORKGROUP
from ..gpu.buffers import uniform_buffer, write_buffer
from ..gpu.kernel import ComputeKernel
from ..gpu.layout import ACCUMULATED_PIXEL
from ..kernels.compile import tracing_kernel
from ..render.renderer import Renderer, RenderStats
from ..scene import Sensor

# Bands are whole rows of the path tracer's workgroups.
BAND_ROWS_STEP = IMAGE_WORKGROUP[1]
# A call never runs more whole passes than this, however fast they are: the frame must end.
MAX_PASSES_PER_CALL = 16
# The cost estimate follows each measurement by this fraction: fast enough to follow a camera
# that turns from a wall to a detailed object, slow enough that one hiccup does not halve a band.
COST_SMOOTHING = 0.3


class BandedRenderer:
    """Adds samples to `renderer`'s accumulation band by band; counts them in `samples_per_pixel`
    (whole passes, kept in the renderer's stats) and `rows_done` (rows of the pass under way that
    have their sample)."""

    def __init__(self, renderer: Renderer) -> None:
        self.renderer = renderer
        self.context = renderer.context
        self.full_size = (renderer.width, renderer.height)
        self._band = uniform_buffer(self.context, "band first row", np.zeros(1, np.uint32))
        self._band_group = self.kernel.bind("band", band_first_row=self._band)
        self.size = self.full_size
        self.rows_done = 0
        # seconds per pixel-sample, measured; None until the first band has run
        self.seconds_per_sample: float | None = None
        # rows [first, end) whose samples changed since take_touched_rows() was last asked
        self._touched: tuple[int, int] | None = None
        self._warm_kernel: ComputeKernel | None = None
        self._warm_up(self.kernel)

    def _warm_up(self, kernel: ComputeKernel) -> None:
        # llvmpipe compiles a pipeline at its first dispatch, which would count as seconds per
        # sample; a band starting below the last row compiles it and touches no pixel. Again for
        # each new variant (the G-buffer one once the moving picture has run, another camera kind).
        write_buffer(self.context, self._band, 0, np.array([self.full_size[1]], np.uint32))
        kernel.dispatch((1, 1), self._bind_groups, wait=True)
        self._warm_kernel = kernel

    @property
    def kernel(self) -> ComputeKernel:
        """The renderer's own path tracer as it is now (material kinds, overrides, guides on or off),
        compiled once more with the band-of-rows entry point (cached per variant)."""
        return tracing_kernel(self.context, replace(self.renderer.variant, rows=True))

    @property
    def _bind_groups(self) -> dict:
        return {**self.renderer.bind_groups, "band": self._band_group}

    @property
    def samples_per_pixel(self) -> int:
        """Whole passes the accumulation holds: the renderer's count, which its own render() and
        restart() keep too."""
        return self.renderer.stats.samples_per_pixel

    @samples_per_pixel.setter
    def samples_per_pixel(self, samples: int) -> None:
        self.renderer.stats.samples_per_pixel = samples

    @property
    def reduced(self) -> bool:
        return self.size != self.full_size

    def restart(self, camera: Sensor, size: tuple[int, int] | None = None) -> None:
        """Forget all samples; trace `size` pixels (at most the full size) through `camera`."""
        width, height = size or self.full_size
        if not (1 <= width <= self.full_size[0] and 1 <= height <= self.full_size[1]):
            raise ValueError(
                f"size {width}x{height} must lie within the renderer's {self.full_size[0]}x{self.full_size[1]}"
            )
        self.renderer.scene.camera = camera
        if camera.kind != self.renderer.variant.scene.camera:
            self.renderer.update()  # another kind of camera: another kernel
        record = self.renderer.frame_record(width, height)
        resources = self.renderer.resources
        write_buffer(self.context, resources["frame"], 0, record)
        encoder = self.context.device.create_command_encoder()
        # only the pixels that will be traced: clearing 10 MB per frame while moving costs time
        encoder.clear_buffer(resources["accumulation"], 0, width * height * ACCUMULATED_PIXEL.size)
        if "guide_sums" in resources:
            encoder.clear_buffer(resources["guide_sums"], 0, 2 * width * height * ACCUMULATED_PIXEL.size)
        self.context.submit(encoder, "the viewer's restart")
        self.size, self.rows_done = (width, height), 0
        self.renderer.stats = RenderStats()
        self._touched = (0, height)

    def rows_for(self, seconds: float) -> int:
        """Rows of the current size that the cost estimate says fit in `seconds` (one band before
        anything has been measured)."""
        if self.seconds_per_sample is None:
            return BAND_ROWS_STEP
        return int(seconds / (self.seconds_per_sample * self.size[0]))

    def advance(self, budget_seconds: float, *, whole_pass: bool = False) -> float:
        """Render what fits in `budget_seconds`: whole passes, or the next band of rows (at least
        one whole pass with `whole_pass`, from the start of a pass). Returns the seconds it took
        (it waits for the adapter), a new kernel variant's compilation included."""
        height = self.size[1]
        rows = self.rows_for(budget_seconds)
        if whole_pass and self.rows_done == 0:
            rows = max(rows, height)
        if self.rows_done == 0 and rows >= height:
            passes, first_row, band_rows = min(rows // height, MAX_PASSES_PER_CALL), 0, height
        else:
            band = max(rows // BAND_ROWS_STEP * BAND_ROWS_STEP, BAND_ROWS_STEP)
            passes, first_row, band_rows = 1, self.rows_done, min(band, height - self.rows_done)
        return self._dispatch(first_row, band_rows, passes)

    def add_passes(self, passes: int) -> float:
        """Exactly `passes` samples per pixel more, whatever they cost (benchmarks, tests)."""
        if self.rows_done != 0:
            raise ValueError(f"a pass is under way ({self.rows_done} of {self.size[1]} rows): finish it with advance()")
        return self._dispatch(0, self.size[1], passes)

    def _dispatch(self, first_row: int, band_rows: int, passes: int) -> float:
        width, height = self.size
        begun = time.perf_counter()
        kernel = self.kernel
        if kernel is not self._warm_kernel:
            self._warm_up(kernel)
        write_buffer(self.context, self._band, 0, np.array([first_row], np.uint32))
        start = time.perf_counter()
        kernel.dispatch((width, band_rows), self._bind_groups, repeat=passes, wait=True)
        seconds = time.perf_counter() - start
        measured = seconds / (passes * band_rows * width)
        if self.seconds_per_sample is None:
            self.seconds_per_sample = measured
        else:
            self.seconds_per_sample += COST_SMOOTHING * (measured - self.seconds_per_sample)
        end_row = min(first_row + band_rows, height)
        touched = self._touched or (first_row, end_row)
        self._touched = (min(touched[0], first_row), max(touched[1], end_row))
        self.renderer.stats.render_seconds += seconds
        if first_row + band_rows >= height:
            self.samples_per_pixel += passes
            self.rows_done = 0
        else:
            self.rows_done = first_row + band_rows
        # the caller's frame spent the compilation too (not counted per sample)
        return time.perf_counter() - begun

    def take_touched_rows(self) -> tuple[int, int] | None:
        """Rows [first, end) whose samples changed since the last call (None: nothing changed)."""
        touched, self._touched = self._touched, None
        return touched

    @property
    def samples_done(self) -> float:
        """Samples per pixel so far, counting the pass under way as the fraction of its rows done."""
        return self.samples_per_pixel + self.rows_done / self.size[1]
