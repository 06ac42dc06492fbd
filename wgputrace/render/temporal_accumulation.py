"""Temporal accumulation (the temporal half of SVGF, Schied et al. 2017): each frame's samples are
added to a per-pixel history carried from frame to frame, which is reprojected along the G-buffer's
motion vectors while anything moves. The kernel is shaders/temporal/temporal_accumulation.wgsl.

The history is a Kahan sum of radiance with its length in samples, and the luminance moments of
the demodulated colour (a variance-guided filter's input). While nothing moves a frame's samples
are added as the renderer's accumulation adds them, so a resting camera's picture is the plain
mean of its samples. While something moves each pixel takes the previous history where its
first hit was: bilinear taps that pass the surface, depth and normal tests (DEPTH_RELATIVE_TOLERANCE,
DEPTH_GRADIENT_MARGIN, NORMAL_COS_MIN), demodulated by their albedo; where none pass the pixel
starts again. Its length is capped at MOVING_HISTORY_FRAMES frames, and its colour clamped to a
box about this frame's 3x3 neighbourhood.

Why a colour box: nothing here yet tells lighting that changed from noise (A-SVGF's temporal
gradients need last frame's paths shaded again), and a box about the neighbourhood bounds what a
wrong history can show by what this frame shows nearby, at nine loads per pixel. The box is the
neighbourhood's mean give or take COLOUR_BOX_SIGMAS standard deviations (variance clipping),
widened by as many of the history's own: a min-max box of one sample per pixel sits below the true
mean of noisy, skewed light (through glass, a caustic) in most frames, and darkened a sliding glass
sphere by a quarter. It is applied only while moving, so a resting picture stays unbiased.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import wgpu

from ..gpu.bindings import STORAGE_READ, STORAGE_READ_WRITE, UNIFORM, BindGroup, Binding
from ..gpu.buffers import read_buffer, storage_buffer, uniform_buffer, write_buffer
from ..gpu.device import GpuContext
from ..gpu.kernel import ComputeKernel
from ..gpu.layout import ACCUMULATED_PIXEL, GBUFFER_PIXEL, GpuStruct
from ..kernels.compile import compute_kernel
from .display_constants import GENERATED_DISPLAY_CONSTANTS, display_constants

GENERATED_TEMPORAL = "generated/temporal.wgsl"

# While anything moves, the history keeps at most this many frames' samples: a wrong history (a
# reflection that moved differently, a lighting change) fades within about as many frames.
# Measured on the Cornell box at 80x60, one sample per frame, the camera sliding 0.012 and turning
# 0.8 degrees a frame: relative MSE of frames 24-39 against 128-sample references of each frame
# 0.27, 0.13, 0.094, 0.086, 0.085 for caps 4, 8, 16, 32, 64. 16 is within a tenth of where longer
# histories stop helping (the reprojection's blur and the clamp then dominate), and lets a stale
# history linger half as long as 32.
MOVING_HISTORY_FRAMES = 16
# A moving history is clamped to this frame's 3x3 neighbourhood mean give or take this many of its
# standard deviations, widened by as many of the history's own (shaders/temporal/history.wgsl).
# Measured on bench.realtime's moving objects at 320x240, the mean over an 80x80 region on the
# sliding glass sphere, frames 20-39, against 32-spp references (0.255, 0.163, 0.172): the
# neighbourhood's min-max box kept (0.202, 0.123, 0.116), the mean +- 1 or 1.5 or 2 standard
# deviations 0.193-0.197 in red, widened by the history's own 1 or 1.5 of them (0.233, 0.147,
# 0.155) and (0.236, 0.148, 0.158), no clamp (0.245, 0.153, 0.164). Mean FLIP over 30 frames of
# the fly-throughs, one sample per pixel, filtered: 0.143 / 0.072 / 0.239 with the min-max box,
# 0.118 / 0.067 / 0.207 with this one.
COLOUR_BOX_SIGMAS = 1.5
# A tap sees this pixel's surface when its depth is within this fraction of the point's distance
# from the previous camera, plus DEPTH_GRADIENT_MARGIN times the depth's change over one pixel
# on this surface (the taps are up to a pixel away in each axis).
DEPTH_RELATIVE_TOLERANCE = 0.02
DEPTH_GRADIENT_MARGIN = 1.5
# ... and its normal within about 25 degrees of this pixel's.
NORMAL_COS_MIN = 0.9
# Taps of a smaller bilinear weight are left out: they would add next to nothing, and counting
# them would let a motion vector's rounding decide whether a pixel's history survives.
BILINEAR_WEIGHT_MIN = 1e-3

TEMPORAL_PIXEL = GpuStruct(
    "TemporalPixel",
    (("sum", "vec4<f32>"), ("compensation", "vec4<f32>"), ("moments", "vec2<f32>"), ("length", "f32")),
    "A pixel's history: the Kahan sum of its radiance samples (sum.w counts non-finite frames), the "
    "means of the demodulated colour's luminance and its square, and how many samples it holds.",
)
TEMPORAL_PARAMETERS = GpuStruct(
    "TemporalParameters",
    (
        ("width", "u32"),
        ("height", "u32"),
        ("samples", "u32"),
        ("moving", "u32"),
        ("reset", "u32"),
        ("length_cap", "f32"),
    ),
    "This frame: its size and samples per pixel, whether anything moved since the last (1: "
    "reproject), whether to start every pixel's history again (1), the history's length cap in samples.",
)


def history_group(name: str, parameters: GpuStruct, *more: Binding) -> BindGroup:
    """The bind group of a pass keeping pixel histories (the bindings shaders/temporal/history.wgsl
    reads): `parameters`, this frame's accumulation and G-buffer, what each pixel of the previous
    history shows, the previous history, the history written, then `more`."""
    return BindGroup(
        name,
        0,
        (
            Binding("params", UNIFORM, parameters),
            Binding("accumulation", STORAGE_READ, ACCUMULATED_PIXEL),
            Binding("gbuffer", STORAGE_READ, GBUFFER_PIXEL),
            Binding("previous_surfaces", STORAGE_READ, GBUFFER_PIXEL),
            Binding("previous_history", STORAGE_READ, TEMPORAL_PIXEL),
            Binding("history", STORAGE_READ_WRITE, TEMPORAL_PIXEL),
            *more,
        ),
    )


# a pixel's history shows what its pixel of the previous G-buffer saw
TEMPORAL_GROUP = history_group("temporal", TEMPORAL_PARAMETERS)


def generated_wgsl(namespace: Mapping[str, object], structs: Sequence[GpuStruct], constants: Sequence[str] = ()) -> str:
    """A generated WGSL file of the module whose globals are `namespace`: its `structs`, then its
    f32 `constants` by name."""
    contents = "structs and constants" if constants else "structs"
    lines = [f"// Generated by {namespace['__name__']}: {contents}."]
    lines += [struct.wgsl() for struct in structs]
    lines += [f"const {name}: f32 = {namespace[name]!r};" for name in constants]
    return "\n".join(lines) + "\n"


def temporal_constants() -> str:
    """The WGSL of GENERATED_TEMPORAL: the history's struct and the consistency tests' constants."""
    constants = (
        "DEPTH_RELATIVE_TOLERANCE",
        "DEPTH_GRADIENT_MARGIN",
        "NORMAL_COS_MIN",
        "BILINEAR_WEIGHT_MIN",
        "COLOUR_BOX_SIGMAS",
    )
    return generated_wgsl(globals(), (TEMPORAL_PIXEL, TEMPORAL_PARAMETERS), constants)


def history_image(records: np.ndarray, width: int, height: int) -> np.ndarray:
    """The mean of each of a `width` x `height` image's histories (TEMPORAL_PIXEL `records`,
    row-major): float32 (height, width, 3), linear radiance, row 0 on top; the sums are subtracted
    and divided in float64, as the Renderer's image() does, and a pixel without history is black (as
    history_mean in shaders/temporal/history_mean.wgsl)."""
    total = records["sum"][:, :3].astype(np.float64) - records["compensation"][:, :3]
    length = records["length"][:, None].astype(np.float64)
    mean = np.divide(total, length, out=np.zeros_like(total), where=length > 0.0)
    return mean.astype(np.float32).reshape(height, width, 3)


_kernels: dict[tuple[int, str], ComputeKernel] = {}


def temporal_pass_kernel(context: GpuContext, entry: str, group: BindGroup, generated: dict[str, str]) -> ComputeKernel:
    """The kernel of a temporal pass: `entry` (a shader file) with its one bind group `group`, the
    display constants and the `generated` files, compiled once per device."""
    key = (id(context.device), entry)
    if key not in _kernels:
        files = {GENERATED_DISPLAY_CONSTANTS: display_constants(), **generated}
        _kernels[key] = compute_kernel(context, entry, (group,), generated=files)
    return _kernels[key]


class HistoryPass:
    """What a pass keeping the histories of a `width` x `height` image holds: its kernel (`entry`
    with the bind group `group`, history_group's, and the `generated` files besides the history's),
    the parameters, the history it writes and the one the next frame takes (`label` names their
    buffers); `_run` runs it on a frame."""

    def __init__(
        self,
        context: GpuContext,
        width: int,
        height: int,
        entry: str,
        group: BindGroup,
        generated: dict[str, str],
        label: str,
    ) -> None:
        self.context, self.width, self.height, self._group = context, width, height, group
        # the generated files its kernels include
        self._generated = {GENERATED_TEMPORAL: temporal_constants(), **generated}
        self.kernel = temporal_pass_kernel(context, entry, group, self._generated)
        pixels = width * height
        # history_group's first binding
        self._parameters = group.bindings[0].holds
        self._params = uniform_buffer(context, f"{label} parameters", self._parameters.zeros(1))
        self.history = storage_buffer(context, f"{label} history", TEMPORAL_PIXEL.zeros(pixels), read_back=True)
        self._previous_history = storage_buffer(context, f"previous {label} history", TEMPORAL_PIXEL.zeros(pixels))
        # the first frame has no history to take
        self._fresh = True
        # whether the last frame took a history reprojected from the one before (something moved)
        self.reprojected = False

    def _run(
        self,
        samples: int,
        moving: bool,
        length_cap: int,
        resources: dict[str, wgpu.GPUBuffer],
        kept: tuple[tuple[wgpu.GPUBuffer, wgpu.GPUBuffer], ...],
        before: tuple[tuple[ComputeKernel, tuple[int, int]], ...] = (),
        **fields: int,
    ) -> None:
        """Run the kernel over the image for a frame of `samples` samples per pixel (`moving`: the
        camera or the scene changed since the previous frame; `length_cap`: the history's in
        samples; `fields`: the further parameters), with `resources` bound besides the parameters
        and histories, after each (kernel, size) of `before` (kernels of the same bind group); then
        copy the history, and each (written, next frame's) pair of `kept`, for the next frame."""
        params = self._parameters.zeros(1)
        params["width"], params["height"], params["samples"] = self.width, self.height, samples
        params["moving"], params["reset"], params["length_cap"] = moving, self._fresh, length_cap
        for name, value in fields.items():
            params[name] = value
        write_buffer(self.context, self._params, 0, params)
        group = self.kernel.bind(
            self._group.name,
            params=self._params,
            previous_history=self._previous_history,
            history=self.history,
            **resources,
        )
        encoder = self.context.device.create_command_encoder()
        for kernel, size in (*before, (self.kernel, (self.width, self.height))):
            compute = encoder.begin_compute_pass()
            kernel.set_bind_groups(compute, {self._group.name: group})
            compute.dispatch_workgroups(*kernel.workgroups(size))
            compute.end()
        for written, next_frames in ((self.history, self._previous_history), *kept):
            encoder.copy_buffer_to_buffer(written, 0, next_frames, 0, written.size)
        self.context.submit(encoder, self._group.name)
        self.reprojected = moving and not self._fresh
        self._fresh = False

    @property
    def carried(self) -> wgpu.GPUBuffer:
        """The history the next frame takes (`_run` copies `history` into it): what SVGF's
        feedback replaces while moving."""
        return self._previous_history

    @property
    def buffers(self) -> tuple[wgpu.GPUBuffer, ...]:
        """Its GPU buffers: the parameters, the history and the previous history."""
        return (self._params, self.history, self._previous_history)

    def restart(self) -> None:
        """Start every pixel's history again at the next frame."""
        self._fresh = True

    @property
    def fresh(self) -> bool:
        """Whether the next frame starts every pixel's history again (the first, after `restart`)."""
        return self._fresh

    def records(self) -> np.ndarray:
        """The history as TEMPORAL_PIXEL records, row-major."""
        return read_buffer(self.context, self.history, TEMPORAL_PIXEL.dtype, self.width * self.height)


class TemporalAccumulation(HistoryPass):
    """The history of an image of `width` x `height` and the previous frame's G-buffer, which
    `add_frame` updates from a frame's accumulation and G-buffer."""

    def __init__(self, context: GpuContext, width: int, height: int) -> None:
        super().__init__(context, width, height, "temporal/temporal_accumulation.wgsl", TEMPORAL_GROUP, {}, "temporal")
        self._previous_gbuffer = storage_buffer(context, "previous G-buffer", GBUFFER_PIXEL.zeros(width * height))

    def add_frame(self, accumulation: wgpu.GPUBuffer, gbuffer: wgpu.GPUBuffer, samples: int, moving: bool) -> None:
        """Add a frame of `samples` samples per pixel (their Kahan sums in `accumulation`, its
        G-buffer in `gbuffer`) to the history; `moving`: the camera or the scene changed since the
        previous frame, whose history is then reprojected."""
        resources = {"accumulation": accumulation, "gbuffer": gbuffer, "previous_surfaces": self._previous_gbuffer}
        self._run(samples, moving, MOVING_HISTORY_FRAMES * samples, resources, ((gbuffer, self._previous_gbuffer),))

    @property
    def buffers(self) -> tuple[wgpu.GPUBuffer, ...]:
        """Its GPU buffers: the parameters, the history, the previous history and G-buffer."""
        return (*super().buffers, self._previous_gbuffer)

    def image(self) -> np.ndarray:
        """Each pixel's mean over its history (history_image)."""
        return history_image(self.records(), self.width, self.height)
