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
distance to the traced pixel. `surfaces` carries what each history shows from frame to frame.
Taps are demodulated by their albedo and the mean clamped to the box about this frame's samples
around, as temporal accumulation does. A pixel the frame did not trace then adds this frame's
samples interpolated over it (bilinear over the traced pixels around it that see the surface its
history shows, demodulated, remodulated by that surface's albedo), each counted as
INTERPOLATED_SAMPLE_WEIGHT of a sample: as FSR 2 and TAAU let every sample reach the pixels around
it, so that a pixel gains something every frame instead of once every f * f frames. A pixel's
history holds at most `history_cap` samples: MOVING_HISTORY_FRAMES frames' worth of what it gains.
A pixel without history (the first frames, disocclusions) shows this frame's samples interpolated
(from the traced pixels that see the nearest one's surface), never black where they are not and
never NaN.

`shown` holds the picture as histories (each pixel's, or the interpolated frame's samples where
it has none) and `surfaces` what each shows: the variance-guided filter's input where frames are
upsampled.
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
    temporal_pass_kernel,
)

GENERATED_UPSAMPLING = "generated/upsampling.wgsl"

# The scale factors render_frame(upscale=...) takes: powers of two, whose blocks the Bayer order
# of `subset_offset` covers.
UPSCALE_FACTORS = (2, 4, 8)
# While anything moves, a pixel the frame did not trace adds the frame's samples interpolated from
# the traced pixels around it (on its surface), each counted as this part of a sample: without
# them a pixel traced once every 16 or 64 frames would hold one sample of its own at most. Measured
# with bench.realtime's fly-throughs at 320x240, one sample per traced pixel, 30 frames: mean FLIP
# at 4x 0.195, 0.194, 0.194 (Cornell box), 0.120, 0.120, 0.120 (asset), 0.305, 0.303, 0.302
# (moving objects) for weights 0.25, 0.5 and 1, against 0.237, 0.155 and 0.377 without them; the
# middle one is taken, as the choice barely matters.
INTERPOLATED_SAMPLE_WEIGHT = 0.5
# The base-4 digits of a frame's index, most significant position bit first: each picks one
# quadrant of the block at its level, the diagonal first (Bayer's 2 x 2 matrix).
_BAYER_STEPS = ((0, 0), (1, 1), (1, 0), (0, 1))

UPSAMPLING_PARAMETERS = GpuStruct(
    "UpsamplingParameters",
    (*TEMPORAL_PARAMETERS.fields, ("factor", "u32"), ("offset_x", "u32"), ("offset_y", "u32")),
    "This frame as TemporalParameters (the full image's size, its samples per traced pixel), with the "
    "block's side and the traced pixel's place in each block.",
)
TRACED_NEIGHBOURHOOD = GpuStruct(
    "TracedNeighbourhood",
    (("low", "vec3<f32>"), ("gradient_x", "f32"), ("high", "vec3<f32>"), ("gradient_y", "f32")),
    "What the rebuilding reads of a traced pixel (shaders/temporal/traced_neighbourhoods.wgsl): the "
    "box about this frame's demodulated colours of the traced pixels around it, and the depth's change "
    "per pixel on its surface along x and y.",
)
# what each pixel's history shows, the picture (`shown`) and each traced pixel's neighbourhood,
# besides the histories
UPSAMPLING_GROUP = history_group(
    "upsampling",
    UPSAMPLING_PARAMETERS,
    Binding("surfaces", STORAGE_READ_WRITE, GBUFFER_PIXEL),
    Binding("shown", STORAGE_READ_WRITE, TEMPORAL_PIXEL),
    Binding("traced", STORAGE_READ_WRITE, TRACED_NEIGHBOURHOOD),
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


def frame_gain(factor: int, samples: int) -> float:
    """The samples a moving pixel's history gains a frame, on average, in frames of `samples`
    samples per traced pixel: its own every factor * factor frames and the interpolated ones
    (INTERPOLATED_SAMPLE_WEIGHT of a sample each) in the others."""
    own = 1.0 / (factor * factor)
    return samples * (own + INTERPOLATED_SAMPLE_WEIGHT * (1.0 - own))


def history_cap(factor: int, samples: int) -> float:
    """The most samples a moving pixel's history keeps: MOVING_HISTORY_FRAMES frames' worth of what
    it gains (`frame_gain`).

    A stale history (a reflection that moved differently, a lighting change) then fades within
    as many frames as temporal accumulation's (MOVING_HISTORY_FRAMES, measured there).
    """
    return MOVING_HISTORY_FRAMES * frame_gain(factor, samples)


def upsampling_constants() -> str:
    """The WGSL of GENERATED_UPSAMPLING: the parameters' and traced pixels' structs and
    INTERPOLATED_SAMPLE_WEIGHT."""
    return generated_wgsl(globals(), (UPSAMPLING_PARAMETERS, TRACED_NEIGHBOURHOOD), ("INTERPOLATED_SAMPLE_WEIGHT",))


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
        self.blocks = (-(-width // factor), -(-height // factor))
        self._traced = storage_buffer(
            context, "traced neighbourhoods", TRACED_NEIGHBOURHOOD.zeros(self.blocks[0] * self.blocks[1])
        )
        # before the rebuilding, each traced pixel's neighbourhood, once
        self._neighbourhoods = temporal_pass_kernel(
            context, "temporal/traced_neighbourhoods.wgsl", UPSAMPLING_GROUP, self._generated
        )
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
        submit(self.context, [Pass(kernel, self.blocks, groups)] * samples, wait=True)

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
            "traced": self._traced,
        }
        offset_x, offset_y = self.offset
        length_cap = history_cap(self.factor, samples)
        kept = ((self.surfaces, self._previous_surfaces),)
        fields = {"factor": self.factor, "offset_x": offset_x, "offset_y": offset_y}
        self._run(samples, moving, length_cap, resources, kept, before=((self._neighbourhoods, self.blocks),), **fields)
        self.frame += 1

    @property
    def buffers(self) -> tuple[wgpu.GPUBuffer, ...]:
        """Its GPU buffers: the parameters, the histories, the subset, what the histories show, the
        picture and the traced pixels' neighbourhoods."""
        return (*super().buffers, self._subset, self.surfaces, self._previous_surfaces, self.shown, self._traced)

    def restart(self) -> None:
        """Start every pixel's history again at the next frame, and the Bayer order at its first pixel."""
        super().restart()
        self.frame = 0

    def image(self) -> np.ndarray:
        """The picture (`shown`, through history_image): each pixel's mean over its history where it
        has one, else the last frame's samples interpolated."""
        records = read_buffer(self.context, self.shown, TEMPORAL_PIXEL.dtype, self.width * self.height)
        return history_image(records, self.width, self.height)
