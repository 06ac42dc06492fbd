"""What a frame shows, as linear colour on the GPU: the accumulated mean (optionally through the
pre-convergence filter) or a debug view (normal, albedo, depth, BVH steps), never read back.

The guides (first hit through each pixel's centre, shaded as the path tracer shades it) are traced
once per camera. The filter is an edge-avoiding a-trous wavelet (Dammertz et al. 2010) on radiance
over albedo, its edges stopped by the guides, blended with the mean by a weight that reaches zero
at FILTER_FADE_SPP (from there on the picture is the mean, bit for bit); it is the expensive
part, so it runs again only once the samples have grown by FILTER_REFRESH_GROWTH.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..gpu.buffers import uniform_buffer, write_buffer
from ..gpu.device import GpuContext
from ..gpu.graphics import copy_texture, image_texture, read_texture
from ..gpu.kernel import ComputeKernel, Pass, submit
from ..kernels.compile import compute_kernel
from ..kernels.variant import KernelVariant, SceneFeatures
from ..render.display_constants import GENERATED_DISPLAY_CONSTANTS, display_constants
from .banded import BandedRenderer
from .layout import (
    ATROUS_GROUP,
    ATROUS_PARAMS,
    GENERATED_VIEW_STRUCTS,
    GUIDE_FORMAT,
    GUIDES_GROUP,
    IMAGE_FORMAT,
    RESOLVE_GROUP,
    RESOLVE_PARAMS,
    ResolveMode,
    View,
    generated_view_structs,
)
from .temporal_picture import DEFAULT_FRAME_VIEW, FrameView

# a-trous passes: taps 1, 2, 4, 8, 16 pixels apart, a footprint of 2 * 2 * (1 + 2 + 4 + 8 + 16) + 1 = 125 pixels.
FILTER_PASSES = 5
# Edge stops (`python -m bench.filter_psnr` measures the filter with these): normals must agree to
# cos^NORMAL_POWER, depths within DEPTH_SIGMA of the distance per tap spacing, albedos within
# ALBEDO_SIGMA (linear RGB distance).
FILTER_NORMAL_POWER = 64.0
FILTER_DEPTH_SIGMA = 0.02
FILTER_ALBEDO_SIGMA = 0.1
# The filter's weight falls linearly in log2(spp) from 1 at one sample to 0 here: its bias stays
# while the noise it removes shrinks as 1/sqrt(spp), so its use ends where the mean is clean.
FILTER_FADE_SPP = 256
# The filtered image is recomputed once the samples per pixel have grown by this factor.
FILTER_REFRESH_GROWTH = 1.25
# The heat map's colour ramp ends at 2^HEAT_LOG2_MAX - 1 BVH nodes visited by a primary ray.
HEAT_LOG2_MAX = 7.0


def filter_weight(samples_per_pixel: float) -> float:
    """How much of the filtered picture a frame shows at this many samples per pixel: 1 at 1 spp
    (or fewer), falling linearly in log2(spp) to 0 at FILTER_FADE_SPP."""
    if samples_per_pixel <= 1.0:
        return 1.0
    return max(0.0, 1.0 - math.log2(samples_per_pixel) / math.log2(FILTER_FADE_SPP))


@dataclass
class ViewSettings:
    view: View = View.RADIANCE
    filter_enabled: bool = False
    depth_scale: float = 1.0  # distance shown black in the depth view: the scene's diagonal
    fade: bool = True  # False: the filter at full weight at any sample count (`python -m bench.filter_psnr`)
    frame_view: FrameView = DEFAULT_FRAME_VIEW  # what the moving picture shows (key V, TemporalPicture)


class Display:
    """Resolves a BandedRenderer's buffers into a linear image texture each frame."""

    def __init__(self, banded: BandedRenderer) -> None:
        self.banded = banded
        self.context = context = banded.context
        renderer = banded.renderer
        width, height = banded.full_size
        generated = {GENERATED_VIEW_STRUCTS: generated_view_structs(), GENERATED_DISPLAY_CONSTANTS: display_constants()}
        self._resolve_kernel = compute_kernel(context, "view/resolve.wgsl", (RESOLVE_GROUP,), generated=generated)
        self._atrous_kernel = compute_kernel(context, "view/atrous.wgsl", (ATROUS_GROUP,), generated=generated)
        self.guides = image_texture(context, "pixel guides", width, height, GUIDE_FORMAT)
        self._compile_guides(renderer.variant.scene)
        self.resolved = image_texture(context, "resolved image", width, height, IMAGE_FORMAT)
        self._demodulated = image_texture(context, "demodulated image", width, height, IMAGE_FORMAT)
        self._ping_pong = [image_texture(context, f"filter {k}", width, height, IMAGE_FORMAT) for k in range(2)]
        self._filtered = image_texture(context, "filtered image", width, height, IMAGE_FORMAT)
        self._fallback = image_texture(context, "fallback image", width, height, IMAGE_FORMAT)
        self._fallback_size = (0, 0)
        self._resolve_params = uniform_buffer(context, "resolve params", RESOLVE_PARAMS.zeros(1))
        self._atrous_params = [
            uniform_buffer(context, f"a-trous params {k}", ATROUS_PARAMS.zeros(1)) for k in range(FILTER_PASSES)
        ]
        resolve_inputs = {
            "params": self._resolve_params,
            "accumulation": renderer.resources["accumulation"],
            "guides": self.guides,
            "fallback": self._fallback,
            "filtered": self._filtered,
        }
        self._resolve_groups = {
            target_name: {"resolve": self._resolve_kernel.bind("resolve", **resolve_inputs, resolved=target)}
            for target_name, target in (("resolved", self.resolved), ("demodulated", self._demodulated))
        }
        # pass k reads the demodulated image (k = 0) or the previous pass's output; the last writes `filtered`
        self._atrous_groups = []
        for k in range(FILTER_PASSES):
            source = self._demodulated if k == 0 else self._ping_pong[(k - 1) % 2]
            target = self._filtered if k == FILTER_PASSES - 1 else self._ping_pong[k % 2]
            group = self._atrous_kernel.bind(
                "atrous", params=self._atrous_params[k], guides=self.guides, source=source, filtered_out=target
            )
            self._atrous_groups.append({"atrous": group})
        self._guides_current = False
        self._filtered_at: float | None = None  # samples per pixel when `filtered` was made
        self._resolved_as: tuple | None = None  # what `resolved` shows where no sample changed since
        self.filter_weight = 0.0  # the weight the last frame showed the filter with

    def keep_as_fallback(self, size: tuple[int, int], source=None) -> None:
        """Show the resolved image of the last frame (`size` pixels; or of the texture `source`, an
        IMAGE_FORMAT one such as the moving picture's), scaled up, where the next passes have no
        sample yet: the last preview frame while the first full pass comes in."""
        copy_texture(self.context, self.resolved if source is None else source, self._fallback, size)
        self._fallback_size = size

    def camera_changed(self) -> None:
        """The guides and the filtered image are stale (call after BandedRenderer.restart)."""
        self._guides_current = False
        self._filtered_at = None
        self._resolved_as = None

    def _compile_guides(self, features: SceneFeatures) -> None:
        """Compile the guides kernel for the renderer's scene `features` (its traversal, shading
        normals, textures and see-through surfaces, as the renderer's kernel has them) and trace
        the guides again with it."""
        self._guides_kernel = guides_kernel(self.context, features)
        self._guides_group = self._guides_kernel.bind("guides", guides=self.guides)
        self._guides_features = features
        self._guides_current = False

    def _resolve_params_record(
        self, settings: ViewSettings, mode: ResolveMode, weight: float, first_row: int = 0
    ) -> np.ndarray:
        width, height = self.banded.size
        record = RESOLVE_PARAMS.zeros(1)
        record["width"], record["height"] = width, height
        record["samples_per_pixel"], record["rows_done"] = self.banded.samples_per_pixel, self.banded.rows_done
        record["view"], record["mode"] = int(settings.view), int(mode)
        record["depth_scale"], record["heat_log2_max"] = settings.depth_scale, HEAT_LOG2_MAX
        record["fallback_width"], record["fallback_height"] = self._fallback_size
        record["filter_weight"] = weight
        record["first_row"] = first_row
        return record

    def _refilter(self) -> None:
        """Demodulate the current mean and run the a-trous passes into `filtered`."""
        width, height = self.banded.size
        radiance = ViewSettings()
        write_buffer(
            self.context, self._resolve_params, 0, self._resolve_params_record(radiance, ResolveMode.DEMODULATED, 0.0)
        )
        size = self.banded.size
        passes = [Pass(self._resolve_kernel, size, self._resolve_groups["demodulated"])]
        for k in range(FILTER_PASSES):
            record = ATROUS_PARAMS.zeros(1)
            record["width"], record["height"], record["step"] = width, height, 1 << k
            record["normal_power"], record["depth_sigma"] = FILTER_NORMAL_POWER, FILTER_DEPTH_SIGMA
            record["albedo_sigma"] = FILTER_ALBEDO_SIGMA
            write_buffer(self.context, self._atrous_params[k], 0, record)
            passes.append(Pass(self._atrous_kernel, size, self._atrous_groups[k]))
        submit(self.context, passes)
        self._filtered_at = self.banded.samples_done

    def render(self, settings: ViewSettings):
        """Resolve the current samples as `settings` asks; returns the texture holding the image
        (the banded renderer's current size, from the top-left corner; row 0 on top)."""
        renderer = self.banded.renderer
        if renderer.variant.scene != self._guides_features:
            self._compile_guides(renderer.variant.scene)
        if not self._guides_current:
            groups = {name: group for name, group in renderer.bind_groups.items() if name in self._guides_kernel.groups}
            self._guides_kernel.dispatch(self.banded.size, {**groups, "guides": self._guides_group})
            self._guides_current = True
        weight = 0.0
        if settings.filter_enabled and settings.view == View.RADIANCE:
            weight = filter_weight(self.banded.samples_done) if settings.fade else 1.0
        if weight > 0.0:
            samples = self.banded.samples_done
            if self._filtered_at is None or samples >= FILTER_REFRESH_GROWTH * self._filtered_at:
                self._refilter()
        mode = ResolveMode.BLENDED if weight > 0.0 else ResolveMode.MEAN
        # Only rows with new samples change, unless what is shown changed or the filter's blend
        # weight (which moves with every sample) is in use. Resolving is a storage load per pixel,
        # the slow kind on CPU adapters: at rest a frame resolves only the band it traced.
        shown_as = (settings.view, settings.depth_scale, mode, self.banded.size, self._fallback_size)
        touched = self.banded.take_touched_rows()
        if shown_as != self._resolved_as or weight > 0.0:
            touched = (0, self.banded.size[1])
        if touched is not None:
            record = self._resolve_params_record(settings, mode, weight, touched[0])
            write_buffer(self.context, self._resolve_params, 0, record)
            rows = (self.banded.size[0], touched[1] - touched[0])
            self._resolve_kernel.dispatch(rows, self._resolve_groups["resolved"])
        self._resolved_as = shown_as
        self.filter_weight = weight
        return self.resolved

    def read_image(self) -> np.ndarray:
        """The last resolved image as float32 (height, width, 3) linear colour (screenshots, tests)."""
        return read_texture(self.context, self.resolved, np.float32, 4, self.banded.size)[:, :, :3].copy()

    def read_guides(self) -> dict[str, np.ndarray]:
        """The guides as decoded arrays (tests): normal (H, W, 3), depth, albedo (H, W, 3), steps."""
        texels = read_texture(self.context, self.guides, np.uint32, 4, self.banded.size)
        return decode_guides(texels)


_guides_kernels: dict[tuple, ComputeKernel] = {}


def guides_kernel(context: GpuContext, features: SceneFeatures) -> ComputeKernel:
    """The guides kernel compiled for a scene's `features`, with their groups (cached per device
    and features, as the renderer's kernels are)."""
    key = (id(context.device), features)
    if key not in _guides_kernels:
        scene, *extras = features.groups()
        generated = {GENERATED_VIEW_STRUCTS: generated_view_structs(), GENERATED_DISPLAY_CONSTANTS: display_constants()}
        _guides_kernels[key] = compute_kernel(
            context,
            "view/first_hit_guides.wgsl",
            (scene, GUIDES_GROUP, *extras),
            KernelVariant(features),
            generated=generated,
        )
    return _guides_kernels[key]


def decode_guides(texels: np.ndarray) -> dict[str, np.ndarray]:
    """The WGSL `unpack_guide` in numpy, for (..., 4) uint32 texels."""
    snorm = np.maximum((texels[..., 0:1] >> np.array([0, 16], np.uint32) & 0xFFFF).astype(np.int16) / 32767.0, -1.0)
    n = np.concatenate([snorm, 1.0 - np.abs(snorm).sum(axis=-1, keepdims=True)], axis=-1)
    folded = (1.0 - np.abs(n[..., 1::-1])) * np.where(n[..., :2] >= 0, 1.0, -1.0)
    n[..., :2] = np.where(n[..., 2:3] < 0, folded, n[..., :2])
    albedo = (texels[..., 2:3] >> np.array([0, 8, 16], np.uint32) & 0xFF) / 255.0
    return {
        "normal": n / np.linalg.norm(n, axis=-1, keepdims=True),
        "depth": texels[..., 1].view(np.float32),
        "albedo": albedo,
        "steps": texels[..., 3],
    }
