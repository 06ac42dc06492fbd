"""The variance-guided filter of SVGF (Schied et al. 2017) on temporal accumulation's history:
each pixel's demodulated illumination and the variance of its luminance (from the history's
moments, or over its neighbourhood where the history is young: shaders/temporal/svgf_variance.wgsl),
then a-trous passes (`svgf_steps`) that stop at depth, normal and luminance edges, the luminance
stop scaled by the filtered variance (shaders/temporal/svgf_atrous.wgsl), and the albedo
multiplied back.

As in SVGF the first a-trous pass's result feeds the next frame's history (shaders/temporal/
svgf_feedback.wgsl), but only for frames in motion (`filter`'s `feedback`): there the history is
capped and clamped already, and the filtered colour lets the next frames start from a smoother
picture; at rest the history stays the plain mean of its samples, so a resting picture converges
to the unbiased mean, bit for bit, whether it is filtered or not.
"""

from __future__ import annotations

import numpy as np
import wgpu

from ..gpu.bindings import STORAGE_READ, STORAGE_READ_WRITE, STORAGE_TEXTURE, TEXTURE_F32, UNIFORM, BindGroup, Binding
from ..gpu.buffers import read_buffer, storage_buffer, uniform_buffer, write_buffer
from ..gpu.device import GpuContext
from ..gpu.graphics import image_texture
from ..gpu.kernel import Pass, submit
from ..gpu.layout import GBUFFER_PIXEL, GpuStruct
from .temporal_accumulation import TEMPORAL_PIXEL, generated_wgsl, temporal_pass_kernel

GENERATED_SVGF = "generated/svgf.wgsl"

# Schied et al.'s choices: depth stop 1 (times the depth's change along the surface's slope),
# normal power 128, luminance stop 4 standard deviations; a history younger than 4 frames estimates
# its variance spatially. Their five a-trous passes spread taps 1 to 16 pixels apart; this filter
# takes fewer (svgf_steps).
SVGF_WIDEST_STEP = 16
# The widest step of a full-resolution picture's passes; an upsampled one's doubles with each
# doubling of the upscale factor, up to SVGF_WIDEST_STEP. Measured with bench.realtime's
# fly-throughs at 320x240, one sample per traced pixel, 30 frames, mean FLIP (Cornell box, asset,
# moving objects) for steps up to 4, 8 and 16 (3, 4 and 5 passes from 1): at 1x 0.143/0.072/0.239,
# 0.145/0.073/0.238, 0.148/0.074/0.239 (three passes as good as five, and two fewer); at 2x
# 0.173/0.089/0.286, 0.173/0.086/0.283, 0.174/0.086/0.282; at 4x 0.197/0.130/0.311,
# 0.194/0.123/0.305, 0.194/0.120/0.303; at 8x 0.230/0.179/0.336, 0.229/0.174/0.331,
# 0.229/0.170/0.329: an upsampled picture's noise spans the traced pixels' spacing, and a wider
# footprint keeps helping there.
SVGF_FULL_RESOLUTION_STEP = 4
# From this upscale factor on, the passes start with taps 2 pixels apart: the interpolated samples
# (INTERPOLATED_SAMPLE_WEIGHT) have smoothed the picture over neighbouring pixels already. Measured
# as above with SVGF's feedback, steps 2 to 16 against 1 to 16: at 4x 0.189/0.125/0.282 against
# 0.191/0.123/0.292, at 8x 0.225/0.171/0.317 against 0.228/0.171/0.325, a pass fewer.
SVGF_SKIP_FIRST_STEP_FROM = 4
# From this upscale factor on, the a-trous passes run at half resolution (a pixel per 2 x 2 block,
# svgf_downsample.wgsl) with half the steps, and the result is brought back by joint bilateral
# upsampling (svgf_upsample.wgsl): the steps start at 2 there anyway, and the passes cost a quarter.
SVGF_HALF_RESOLUTION_FROM = 4
# A half-resolution pixel spans two full ones: the depth's change per pixel doubles.
HALF_RESOLUTION_SLOPE_SCALE = 2.0
# Below this total weight of its half-resolution taps an upsampled pixel keeps its own illumination.
UPSAMPLE_WEIGHT_MIN = 1e-6
SVGF_DEPTH_SIGMA = 1.0
SVGF_NORMAL_POWER = 128.0
# The normal stop raises a cosine to SVGF_NORMAL_POWER by squaring it this many times: cheaper than
# pow's exp2(log2), which lavapipe computes per tap.
assert SVGF_NORMAL_POWER == 2.0 ** round(np.log2(SVGF_NORMAL_POWER)), "the normal power must be a power of two"
SVGF_NORMAL_SQUARINGS = round(np.log2(SVGF_NORMAL_POWER))
SVGF_LUMINANCE_SIGMA = 4.0
# The luminance stop's scale where the passes run at half resolution (SVGF_HALF_RESOLUTION_FROM on):
# a tighter stop, the picture being smoothed already by the interpolated samples and the blocks.
# Measured with bench.realtime's fly-throughs, one sample per traced pixel, 4x (PSNR / FLIP of the
# Cornell box, the asset, the moving objects). At 320x240, frames 8-39: sigma 4 22.70 / 0.177,
# 24.86 / 0.112, 21.34 / 0.250; 2: 23.15 / 0.170, 25.54 / 0.107, 21.54 / 0.246; 1: 23.54 / 0.166,
# 26.23 / 0.102, 21.63 / 0.245. At 640x480, frames 8-19: 4: 24.31 / 0.140, 28.88 / 0.085, 21.28 /
# 0.229; 2: 24.48 / 0.140, 29.24 / 0.083, 21.32 / 0.232; 1: 24.56 / 0.142, 29.47 / 0.083, 21.29 /
# 0.240. 2 gains at both sizes where 1 costs the larger one's FLIP. Below, Schied's 4 is kept: at
# 2x sigma 1 cost the moving objects' FLIP (0.218 -> 0.238), at 1x sigma 2 did too (0.203 -> 0.212).
HALF_RESOLUTION_LUMINANCE_SIGMA = 2.0
SVGF_TEMPORAL_FRAMES = 4
# The depth stop's tolerance beyond the slope, as a fraction of the distance: a surface facing the
# camera (slope 0) would otherwise stop at float rounding.
SVGF_DEPTH_FLOOR = 1e-3
# The luminance stop's smallest scale: a pixel without noise (variance 0) then keeps only taps of
# its own luminance, instead of dividing 0 by 0.
SVGF_SPREAD_MIN = 1e-10
# A pixel's demodulated illumination (rgb) and its luminance's variance (w).
ILLUMINATION = "vec4<f32>"

SVGF_PARAMETERS = GpuStruct(
    "SvgfParameters",
    (
        ("width", "u32"),
        ("height", "u32"),
        ("step", "u32"),
        ("last", "u32"),
        ("temporal_length", "f32"),
        ("luminance_sigma", "f32"),
    ),
    "A pass of the filter: the image's size, the pass's tap spacing, whether it is the last (1: "
    "multiply the albedo back), the history length (samples) from which its own moments count, and "
    "the luminance stop's scale in standard deviations.",
)


# What the a-trous passes' stops read of each pixel, written once a frame by the variance pass so
# that each tap reads 16 bytes instead of a 48-byte GBufferPixel: the normal and the depth
# (SVGF_SKY_DEPTH where the sky was seen), as a texture (lavapipe loads a texel cheaper than a
# storage buffer's element), and the depth's change per pixel along x and y on the pixel's surface
# (depth_gradient, the same in every pass).
GUIDE_FORMAT = "rgba32float"
SLOPE = "vec2<f32>"


def _pass_group(
    name: str, reads: tuple[str, object], writes: tuple[str, object], guides: tuple[Binding, ...] = ()
) -> BindGroup:
    """A pass's bind group: its parameters, the G-buffer, what it reads and what it writes (each a
    binding name and its element type), then the `guides` it reads or writes."""
    return BindGroup(
        name,
        0,
        (
            Binding("params", UNIFORM, SVGF_PARAMETERS),
            Binding("gbuffer", STORAGE_READ, GBUFFER_PIXEL),
            Binding(reads[0], STORAGE_READ, reads[1]),
            Binding(writes[0], STORAGE_READ_WRITE, writes[1]),
            *guides,
        ),
    )


VARIANCE_GROUP = _pass_group(
    "svgf_variance",
    ("history", TEMPORAL_PIXEL),
    ("illuminated", ILLUMINATION),
    (Binding("guides", STORAGE_TEXTURE, GUIDE_FORMAT), Binding("slopes", STORAGE_READ_WRITE, SLOPE)),
)
ATROUS_GROUP = _pass_group(
    "svgf_atrous",
    ("source", ILLUMINATION),
    ("filtered_out", ILLUMINATION),
    (Binding("guides", TEXTURE_F32), Binding("slopes", STORAGE_READ, SLOPE)),
)
# the full-resolution illumination into its half-resolution blocks
DOWNSAMPLE_GROUP = _pass_group(
    "svgf_downsample",
    ("illuminated", ILLUMINATION),
    ("reduced", ILLUMINATION),
    (
        Binding("guides", TEXTURE_F32),
        Binding("slopes", STORAGE_READ, SLOPE),
        Binding("half_guides", STORAGE_TEXTURE, GUIDE_FORMAT),
        Binding("half_slopes", STORAGE_READ_WRITE, SLOPE),
    ),
)
# a half-resolution result back to full resolution, the unfiltered illumination (`own`) beside it
UPSAMPLE_GROUP = _pass_group(
    "svgf_upsample",
    ("source", ILLUMINATION),
    ("filtered_out", ILLUMINATION),
    (
        Binding("own", STORAGE_READ, ILLUMINATION),
        Binding("guides", TEXTURE_F32),
        Binding("half_guides", TEXTURE_F32),
        Binding("slopes", STORAGE_READ, SLOPE),
    ),
)
# the first a-trous pass's output into the history the next frame takes
FEEDBACK_GROUP = _pass_group("svgf_feedback", ("filtered", ILLUMINATION), ("carried", TEMPORAL_PIXEL))


def svgf_steps(upscale: int) -> tuple[int, ...]:
    """The tap spacing of each a-trous pass, in order, for a picture upsampled by `upscale` (1: full
    resolution): doubling from 1 (2 from SVGF_SKIP_FIRST_STEP_FROM on) to SVGF_FULL_RESOLUTION_STEP
    times the factor, at most SVGF_WIDEST_STEP."""
    first = 2 if upscale >= SVGF_SKIP_FIRST_STEP_FROM else 1
    widest = min(SVGF_FULL_RESOLUTION_STEP * upscale, SVGF_WIDEST_STEP)
    return tuple(1 << k for k in range(first.bit_length() - 1, widest.bit_length()))


def luminance_sigma(upscale: int) -> float:
    """The luminance stop's scale, in standard deviations of the luminance, for a picture upsampled
    by `upscale`: Schied et al.'s, or HALF_RESOLUTION_LUMINANCE_SIGMA where the passes run at half
    resolution."""
    return HALF_RESOLUTION_LUMINANCE_SIGMA if upscale >= SVGF_HALF_RESOLUTION_FROM else SVGF_LUMINANCE_SIGMA


def svgf_constants() -> str:
    """The WGSL of GENERATED_SVGF: the filter's struct and constants."""
    constants = (
        "SVGF_DEPTH_SIGMA",
        "SVGF_DEPTH_FLOOR",
        "SVGF_SPREAD_MIN",
        "HALF_RESOLUTION_SLOPE_SCALE",
        "UPSAMPLE_WEIGHT_MIN",
    )
    squarings = f"const SVGF_NORMAL_SQUARINGS: u32 = {SVGF_NORMAL_SQUARINGS}u;\n"
    return generated_wgsl(globals(), (TEMPORAL_PIXEL, SVGF_PARAMETERS), constants) + squarings


def picture_image(context: GpuContext, picture: wgpu.GPUBuffer, width: int, height: int) -> np.ndarray:
    """A `width` x `height` picture (ILLUMINATION per pixel, row-major) read back: float32 (height,
    width, 3), linear radiance, row 0 on top."""
    pixels = read_buffer(context, picture, np.float32, 4 * width * height)
    return pixels.reshape(height, width, 4)[..., :3].copy()


class VarianceGuidedFilter:
    """SVGF's spatial filter for images of `width` x `height`: `filter` reads a history and a G-buffer."""

    def __init__(self, context: GpuContext, width: int, height: int) -> None:
        self.context, self.width, self.height = context, width, height
        generated = {GENERATED_SVGF: svgf_constants()}
        kernels = (
            ("variance", VARIANCE_GROUP),
            ("atrous", ATROUS_GROUP),
            ("feedback", FEEDBACK_GROUP),
            ("downsample", DOWNSAMPLE_GROUP),
            ("upsample", UPSAMPLE_GROUP),
        )
        self._kernels = {
            name: temporal_pass_kernel(context, f"temporal/svgf_{name}.wgsl", group, generated)
            for name, group in kernels
        }
        pixels = np.zeros((width * height, 4), np.float32)
        # ping-pong between two, the last pass into `filtered`
        self._work = [storage_buffer(context, f"SVGF illumination {k}", pixels) for k in range(2)]
        self.filtered = storage_buffer(context, "SVGF filtered", pixels, read_back=True)
        self._guides = image_texture(context, "SVGF guides", width, height, GUIDE_FORMAT)
        self._slopes = storage_buffer(context, "SVGF slopes", np.zeros((width * height, 2), np.float32))
        self.half_size = (-(-width // 2), -(-height // 2))
        blocks = self.half_size[0] * self.half_size[1]
        self._half_work = [
            storage_buffer(context, f"SVGF half-resolution illumination {k}", np.zeros((blocks, 4), np.float32))
            for k in range(2)
        ]
        self._half_guides = image_texture(context, "SVGF half-resolution guides", *self.half_size, GUIDE_FORMAT)
        self._half_slopes = storage_buffer(context, "SVGF half-resolution slopes", np.zeros((blocks, 2), np.float32))
        # one per pass of the longest sequence: the variance, the downsampling, the a-trous passes,
        # the feedback and the two upsamplings (the feedback's and the last)
        self._params = [
            uniform_buffer(context, f"SVGF parameters {k}", SVGF_PARAMETERS.zeros(1))
            for k in range(SVGF_WIDEST_STEP.bit_length() + 5)
        ]

    def _pass(self, name: str, number: int, size: tuple[int, int], step: int = 1, last: bool = False, **bound) -> Pass:
        """A pass of kernel `name` over `size` with parameters buffer `number` (the pass's tap
        spacing `step`, whether it is the `last`, and `bound`'s temporal_length and
        luminance_sigma) and the rest of `bound` bound by name. Only the a-trous passes run at
        `size`'s resolution: the others read the full image's size from their parameters."""
        record = SVGF_PARAMETERS.zeros(1)
        record["width"], record["height"] = size if name == "atrous" else (self.width, self.height)
        record["step"], record["last"], record["temporal_length"] = step, last, bound.pop("temporal_length")
        record["luminance_sigma"] = bound.pop("luminance_sigma")
        write_buffer(self.context, self._params[number], 0, record)
        kernel = self._kernels[name]
        group = kernel.bind(f"svgf_{name}", params=self._params[number], **bound)
        return Pass(kernel, size, {f"svgf_{name}": group})

    def filter(
        self,
        history: wgpu.GPUBuffer,
        gbuffer: wgpu.GPUBuffer,
        samples_per_frame: float,
        feedback: wgpu.GPUBuffer | None = None,
        upscale: int = 1,
    ) -> wgpu.GPUBuffer:
        """The filtered picture of `history` (TEMPORAL_PIXEL records) seen through `gbuffer`, whose
        pixels gain `samples_per_frame` samples a frame (upsampled: on average, `frame_gain`): the
        buffer holding it (`filtered`, ILLUMINATION per pixel, linear radiance in rgb; picture_image
        reads it). A history younger than SVGF_TEMPORAL_FRAMES frames' worth takes its variance
        from its neighbourhood.
        `feedback`: the history the next frame takes (a copy of `history`), whose colour the first
        a-trous pass's result then replaces. `upscale`: the factor the picture was upsampled by,
        which sets the passes (svgf_steps) and their resolution (SVGF_HALF_RESOLUTION_FROM)."""
        full = (self.width, self.height)
        numbers = iter(range(len(self._params)))
        every = {
            "temporal_length": SVGF_TEMPORAL_FRAMES * samples_per_frame,
            "luminance_sigma": luminance_sigma(upscale),
            "gbuffer": gbuffer,
        }
        guides = {"guides": self._guides, "slopes": self._slopes}
        illuminated = self._work[0]
        passes = [
            self._pass("variance", next(numbers), full, history=history, illuminated=illuminated, **guides, **every)
        ]
        steps = svgf_steps(upscale)
        half = upscale >= SVGF_HALF_RESOLUTION_FROM
        if half:
            work, size = self._half_work, self.half_size
            steps = tuple(step // 2 for step in steps)
            half_guides = {"half_guides": self._half_guides, "half_slopes": self._half_slopes}
            passes.append(
                self._pass(
                    "downsample",
                    next(numbers),
                    size,
                    illuminated=illuminated,
                    reduced=work[0],
                    **guides,
                    **half_guides,
                    **every,
                )
            )
            atrous_guides = {"guides": self._half_guides, "slopes": self._half_slopes}
        else:
            work, size, atrous_guides = self._work, full, guides

        def upsampled(source: wgpu.GPUBuffer, target: wgpu.GPUBuffer, last: bool) -> Pass:
            bound = {"source": source, "filtered_out": target, "own": illuminated, "half_guides": self._half_guides}
            return self._pass("upsample", next(numbers), full, last=last, **bound, **guides, **every)

        for number, step in enumerate(steps, start=1):
            source = work[(number - 1) % 2]
            # at full resolution the last pass remodulates into `filtered`; at half, the upsampling
            last = number == len(steps) and not half
            target = self.filtered if last else work[number % 2]
            bound = {"source": source, "filtered_out": target}
            passes.append(self._pass("atrous", next(numbers), size, step, last, **bound, **atrous_guides, **every))
            if number == 1 and feedback is not None:
                filtered = target
                if half:
                    # the full-resolution illumination is read by the last upsampling: the other buffer
                    filtered = self._work[1]
                    passes.append(upsampled(target, filtered, False))
                passes.append(self._pass("feedback", next(numbers), full, filtered=filtered, carried=feedback, **every))
        if half:
            passes.append(upsampled(work[len(steps) % 2], self.filtered, True))
        submit(self.context, passes)
        return self.filtered

    @property
    def buffers(self) -> tuple[wgpu.GPUBuffer, ...]:
        """The filter's buffers (the guides' textures, 16 bytes a pixel, are not)."""
        return (*self._work, self.filtered, self._slopes, *self._half_work, self._half_slopes, *self._params)
