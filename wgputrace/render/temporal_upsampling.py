"""Temporal upsampling for adapters too slow to trace every pixel each frame (`render_frame(upscale=f)`):
each frame traces one pixel of every f x f block (the kernel's main_subset entry), and the full
picture is rebuilt from every pixel's history. The kernel is shaders/temporal/temporal_upsampling.wgsl.

Which pixel of the blocks a frame traces follows `subset_offset`, the order of an f x f Bayer
matrix: a (0, 2)-sequence in base 2 over the block, so any f x f consecutive frames visit every
pixel once and the first frames of a cycle spread over the block (the first four fall in its
four quadrants). A traced pixel takes its own next sample, jittered within it by its own sampler,
exactly as `render()` takes it: at rest, after N * f * f frames of one sample every pixel holds
the first N samples of its sequence, and the picture is bit for bit `render(N)`'s. That is the
same as rendering an image f times smaller through a camera shifted by a sub-pixel offset each
frame (FSR 2's and TAAU's jitter), with each sample's footprint shrunk to its full-resolution
pixel; as every sample lands inside one full-resolution pixel, it is added to that pixel alone,
with weight one (no distance weighting is needed, as in FSR 2, where samples straddle pixels).

While anything moves, every pixel takes the previous history along the motion vector of a traced
pixel (one G-buffer entry per block: the full G-buffer would cost a camera ray per pixel, most of
what a frame saves at 4x): of the four traced pixels around it, the nearest whose surface the
history shows where its motion leads, so a pixel beside an edge moves with its own side. Four
bilinear taps, each kept where the history there shows that surface, with a normal within
NORMAL_COS_MIN and a depth within the temporal tolerances widened by the depth's slope over the
distance to the traced pixel. `surfaces` carries what each history shows from frame to frame. Taps are demodulated by their albedo and
the mean clamped to the box of this frame's samples around, as temporal accumulation does. A
pixel's history holds at most `history_cap` samples: about MOVING_HISTORY_FRAMES frames' worth,
as a pixel takes a sample every f * f frames. A pixel without history (the first frames,
disocclusions) shows this frame's samples interpolated (bilinear over the traced pixels around
it that see the nearest one's surface), never black where they are not and never NaN.

`shown` holds the picture as histories (each pixel's, or the interpolated frame as one sample)
and `surfaces` what each shows: the variance-guided filter's input where frames are upsampled.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import wgpu

from ..gpu.bindings import STORAGE_READ_WRITE, Binding
from ..gpu.buffers import read_buffer, storage_buffer, uniform_buffer, write_buffer
from ..gpu.device import GpuContext
from ..gpu.kernel import Pass, submit
from ..gpu.layout import GBUFFER_PIXEL, GpuStruct
from ..kernels.compile import tracing_kernel
from .temporal_accumulation import (
    MOVING_HISTORY_FRAMES,
    TEMPORAL_PARAMETERS,
    TEMPORAL_PIXEL,
    HistoryPass,
    generated_wgsl,
    history_group,
    history_image,
)

GENERATED_UPSAMPLING = "generated/upsampling.wgsl"

# The scale factors render_frame(upscale=...) takes: powers of two, whose blocks the Bayer order
# of `subset_offset` covers.
UPSCALE_FACTORS = (2, 4, 8)
# The base-4 digits of a frame's index, most significant position bit first: each picks one
# quadrant of the block at its level, the diagonal first (Bayer's 2 x 2 matrix).
_BAYER_STEPS = ((0, 0), (1, 1), (1, 0), (0, 1))

UPSAMPLING_PARAMETERS = GpuStruct(
    "UpsamplingParameters",
    (*TEMPORAL_PARAMETERS.fields, ("factor", "u32"), ("offset_x", "u32"), ("offset_y", "u32")),
    "This frame as TemporalParameters (the full image's size, its samples per traced pixel), with the "
    "block's side and the traced pixel's place in each block.",
)
# what each pixel's history shows and the picture (`shown`), besides the histories
UPSAMPLING_GROUP = history_group(
    "upsampling",
    UPSAMPLING_PARAMETERS,
    Binding("surfaces", STORAGE_READ_WRITE, GBUFFER_PIXEL),
    Binding("shown", STORAGE_READ_WRITE, TEMPORAL_PIXEL),
)


def check_upscale(factor: int, width: int, height: int) -> None:
    """ValueError unless `factor` is one of UPSCALE_FACTORS and an image of `width` x `height`
    holds a whole block of it."""
    if factor not in UPSCALE_FACTORS:
        raise ValueError(f"upscale must be 1 or one of {UPSCALE_FACTORS}, got {factor!r}")
    if width < factor or height < factor:
        raise ValueError(f"upscale {factor} needs an image of at least {factor}x{factor} pixels, got {width}x{height}")


def subset_offset(frame: int, factor: int) -> tuple[int, int]:
    """(x, y) of the pixel that frame number `frame` traces in every `factor` x `factor` block:
    the Bayer matrix's order, periodic in factor * factor frames, each pixel once per period."""
    index = frame % (factor * factor)
    levels = factor.bit_length() - 1
    x = y = 0
    for level in range(levels):
        dx, dy = _BAYER_STEPS[(index >> (2 * level)) & 3]
        x |= dx << (levels - 1 - level)
        y |= dy << (levels - 1 - level)
    return x, y


def history_cap(factor: int, samples: int) -> int:
    """The most samples a moving pixel's history keeps: MOVING_HISTORY_FRAMES frames' worth of a
    pixel's samples, which come every factor * factor frames (at least one frame's).

    Measured on the Cornell box at 64x48, one sample per frame, the camera sliding 0.004 a frame:
    sRGB PSNR of frames 12 and 24 against 256 samples per pixel, for caps of 1, 2, 4, 8, 16
    samples: at 2x 16.67/16.82, 17.01/17.33, 17.09/17.59, 17.09/17.63, 17.09/17.63 dB (this cap
    is 4, within 0.04 dB of the longest); at 4x 14.74/15.19 dB for a cap of 1 (this one), 14.75/
    15.21 for every longer one: a pixel's own samples come every 16 frames, so its history is
    rarely longer than the cap."""
    return max(MOVING_HISTORY_FRAMES // (factor * factor), 1) * samples


def upsampling_constants() -> str:
    """The WGSL of GENERATED_UPSAMPLING: the parameters' struct."""
    return generated_wgsl(globals(), (UPSAMPLING_PARAMETERS,))


class TemporalUpsampling(HistoryPass):
    """The history of a `width` x `height` image rebuilt from one traced pixel per `factor` x
    `factor` block per frame: `trace` adds a frame's samples to a Renderer's accumulation and
    G-buffer at those pixels, `add_frame` takes them into the history."""

    def __init__(self, context: GpuContext, width: int, height: int, factor: int) -> None:
        check_upscale(factor, width, height)
        generated = {GENERATED_UPSAMPLING: upsampling_constants()}
        entry = "temporal/temporal_upsampling.wgsl"
        super().__init__(context, width, height, entry, UPSAMPLING_GROUP, generated, "upsampled")
        self.factor = factor
        pixels = width * height
        self._subset = uniform_buffer(context, "pixel subset", np.zeros(4, np.uint32))
        self.surfaces = storage_buffer(context, "upsampled surfaces", GBUFFER_PIXEL.zeros(pixels), read_back=True)
        self._previous_surfaces = storage_buffer(context, "previous upsampled surfaces", GBUFFER_PIXEL.zeros(pixels))
        # the picture as histories: each pixel's, or where it has none this frame's samples
        # interpolated, as one sample (the variance-guided filter's input too)
        self.shown = storage_buffer(context, "upsampled picture", TEMPORAL_PIXEL.zeros(pixels), read_back=True)
        # the frame's number in the Bayer order since the history began
        self.frame = 0

    @property
    def offset(self) -> tuple[int, int]:
        """The pixel of each block that the next frame traces (`subset_offset`)."""
        return subset_offset(self.frame, self.factor)

    def trace(self, renderer, samples: int) -> None:
        """Add `samples` samples to `renderer`'s accumulation at the next frame's pixels, one per
        block, and write their G-buffer entries (its subset kernel); waits for them."""
        kernel = tracing_kernel(self.context, replace(renderer.variant, subset=True))
        write_buffer(self.context, self._subset, 0, np.array([self.factor, *self.offset, 0], np.uint32))
        groups = {**renderer.bind_groups, "subset": kernel.bind("subset", pixel_subset=self._subset)}
        blocks = (-(-self.width // self.factor), -(-self.height // self.factor))
        submit(self.context, [Pass(kernel, blocks, groups)] * samples, wait=True)

    def add_frame(self, accumulation: wgpu.GPUBuffer, gbuffer: wgpu.GPUBuffer, samples: int, moving: bool) -> None:
        """Take the frame `trace` made (its sums in `accumulation`, its G-buffer in `gbuffer`) into
        every pixel's history; `moving`: the camera or the scene changed since the previous frame,
        whose history is then reprojected."""
        resources = {
            "accumulation": accumulation,
            "gbuffer": gbuffer,
            "previous_surfaces": self._previous_surfaces,
            "surfaces": self.surfaces,
            "shown": self.shown,
        }
        offset_x, offset_y = self.offset
        length_cap = history_cap(self.factor, samples)
        kept = ((self.surfaces, self._previous_surfaces),)
        self._run(
            samples, moving, length_cap, resources, kept, factor=self.factor, offset_x=offset_x, offset_y=offset_y
        )
        self.frame += 1

    @property
    def buffers(self) -> tuple[wgpu.GPUBuffer, ...]:
        """Its GPU buffers: the parameters, the histories, the subset, what the histories show and the picture."""
        return (*super().buffers, self._subset, self.surfaces, self._previous_surfaces, self.shown)

    def restart(self) -> None:
        """Start every pixel's history again at the next frame, and the Bayer order at its first pixel."""
        super().restart()
        self.frame = 0

    def image(self) -> np.ndarray:
        """The picture (`shown`, through history_image): each pixel's mean over its history where it
        has one, else the last frame's samples interpolated."""
        records = read_buffer(self.context, self.shown, TEMPORAL_PIXEL.dtype, self.width * self.height)
        return history_image(records, self.width, self.height)
