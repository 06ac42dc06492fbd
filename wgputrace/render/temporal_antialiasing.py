"""Temporal antialiasing (TAA) of the upsampled, filtered picture, the last stage of SVGF's pipeline
(Schied et al. 2017 run TAA on the filter's output): each pixel blends ANTIALIASING_BLEND of this
frame's filtered picture with the last frame's output, taken along the pixel's motion (bilinear)
and clamped to the smallest and largest colours of this frame's 3x3 neighbourhood. The kernel is
shaders/temporal/temporal_antialiasing.wgsl.

Why after the filter, for upsampled frames: a pixel traced once every f x f frames lives on its
neighbours' interpolated samples, and which pixels were traced changes every frame, so the filtered
picture changes from frame to frame by more than the scene does (its instability, bench.realtime).
Blending outputs averages that change away; the clamp keeps a moved or disoccluded pixel from
showing what this frame's picture around it does not. At full resolution each pixel's history is
its own samples, and the blend bought little there (ANTIALIASING_BLEND's measurements).

Only while moving: at rest the output is the filtered picture itself, which converges as the
history does. After a restart or a change of factor the first frame is its own output.
"""

from __future__ import annotations

import numpy as np
import wgpu

from ..gpu.bindings import STORAGE_READ, STORAGE_READ_WRITE, UNIFORM, BindGroup, Binding
from ..gpu.buffers import storage_buffer, uniform_buffer, write_buffer
from ..gpu.device import GpuContext
from ..gpu.kernel import Pass, submit
from ..gpu.layout import GBUFFER_PIXEL, GpuStruct
from .temporal_accumulation import generated_wgsl, temporal_pass_kernel

GENERATED_ANTIALIASING = "generated/antialiasing.wgsl"

# This frame's part of each moving pixel's output; the last frame's output has the rest.
# Measured with bench.realtime's fly-throughs at 320x240, upsampled 4x, one sample per traced pixel,
# frames 8-39 (mean PSNR, FLIP and instability; the blend emulated on the filter's output): the
# Cornell box 22.26 dB, 0.175, 0.059 without it; 22.66, 0.176, 0.043 at 0.5; 22.71, 0.177, 0.041
# at 0.25; 22.67, 0.178, 0.040 at 0.1. The asset 24.29 dB, 0.113, 0.033 without; 24.72, 0.113,
# 0.021 at 0.25. The moving objects 21.37 dB, 0.248, 0.062 without; 21.31, 0.250, 0.059 at 0.25
# (what changes there is light through the sliding glass sphere, which no blend of outputs
# follows). At full resolution 0.25 took the Cornell box's instability from 0.038 to 0.034 for FLIP
# 0.116 -> 0.121, and made the moving objects' worse (0.0515 -> 0.0523, FLIP 0.203 -> 0.208).
ANTIALIASING_BLEND = 0.25
# A picture's pixel: rgb, and the variance the filter passes on in w.
PICTURE_PIXEL = "vec4<f32>"

ANTIALIASING_PARAMETERS = GpuStruct(
    "AntialiasingParameters",
    (("width", "u32"), ("height", "u32"), ("moving", "u32")),
    "This frame: the image's size, and whether to blend (1: the history moved with the scene; 0: "
    "the output is this frame's picture).",
)
ANTIALIASING_GROUP = BindGroup(
    "antialiasing",
    0,
    (
        Binding("params", UNIFORM, ANTIALIASING_PARAMETERS),
        Binding("gbuffer", STORAGE_READ, GBUFFER_PIXEL),
        Binding("current", STORAGE_READ, PICTURE_PIXEL),
        Binding("previous_output", STORAGE_READ, PICTURE_PIXEL),
        Binding("output", STORAGE_READ_WRITE, PICTURE_PIXEL),
    ),
)


def antialiasing_constants() -> str:
    """The WGSL of GENERATED_ANTIALIASING: the parameters' struct and ANTIALIASING_BLEND."""
    return generated_wgsl(globals(), (ANTIALIASING_PARAMETERS,), ("ANTIALIASING_BLEND",))


class TemporalAntialiasing:
    """The output history of a `width` x `height` picture: `resolve` blends each frame's picture
    into it. Two output buffers take turns: one written, the other the last frame's."""

    def __init__(self, context: GpuContext, width: int, height: int) -> None:
        self.context, self.width, self.height = context, width, height
        generated = {GENERATED_ANTIALIASING: antialiasing_constants()}
        self.kernel = temporal_pass_kernel(
            context, "temporal/temporal_antialiasing.wgsl", ANTIALIASING_GROUP, generated
        )
        self._params = uniform_buffer(context, "antialiasing parameters", ANTIALIASING_PARAMETERS.zeros(1))
        pixels = np.zeros((width * height, 4), np.float32)
        self._outputs = [storage_buffer(context, f"antialiased picture {k}", pixels, read_back=True) for k in range(2)]
        self._written = 0

    def resolve(self, current: wgpu.GPUBuffer, surfaces: wgpu.GPUBuffer, moving: bool) -> wgpu.GPUBuffer:
        """This frame's output from its picture `current` (PICTURE_PIXEL per pixel) whose pixels
        show `surfaces` (G-buffer entries: their motion, and whether the previous camera saw them);
        `moving`: blend with the last frame's output (the picture's history moved with the scene
        since that frame). Returns the buffer holding it, until the next `resolve`."""
        params = ANTIALIASING_PARAMETERS.zeros(1)
        params["width"], params["height"], params["moving"] = self.width, self.height, moving
        write_buffer(self.context, self._params, 0, params)
        previous, self._written = self._outputs[self._written], 1 - self._written
        output = self._outputs[self._written]
        bound = {"params": self._params, "gbuffer": surfaces, "current": current, "previous_output": previous}
        group = self.kernel.bind(ANTIALIASING_GROUP.name, **bound, output=output)
        submit(self.context, [Pass(self.kernel, (self.width, self.height), {ANTIALIASING_GROUP.name: group})])
        return output

    @property
    def buffers(self) -> tuple[wgpu.GPUBuffer, ...]:
        """Its GPU buffers: the parameters and the two outputs."""
        return (self._params, *self._outputs)
