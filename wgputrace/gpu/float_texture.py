"""An rgba32float texture following a float32 (H, W, 4) array, or an rgba8unorm one following a
uint8 array (read as floats in [0, 1]), with TrackedBuffer's interface (`upload`, `generation`,
`uploads`, `capacity_bytes`, `resource`): the environment map and the texture atlas (`Atlas`).

Shaders read it with textureLoad and filter by hand (`environment_texel`): filtering float32
textures is an optional WebGPU feature. An upload writes the rows given as changed, one write per
run, or the whole texture; another size or texel type reallocates it and bumps `generation`, so
the owner rebinds. wgpu's errors come out as GpuFailure naming the texture.
"""

from __future__ import annotations

import numpy as np
import wgpu

from .device import GpuContext, reporting
from .tracked_buffer import UploadCount, merged_runs

TEXEL_CHANNELS = 4
# the texture format holding each texel type
FORMATS = {np.dtype(np.float32): wgpu.TextureFormat.rgba32float, np.dtype(np.uint8): wgpu.TextureFormat.rgba8unorm}


def require_float_texture(context: GpuContext, label: str, width: int, height: int) -> None:
    """DeviceLimitError unless a `width` x `height` texture fits the adapter, naming the texture."""
    what = f"texture {label!r} ({width:,}x{height:,} texels)"
    context.require("max-texture-dimension-2d", max(width, height), what)


class FloatTexture:
    def __init__(self, context: GpuContext, label: str, data: np.ndarray) -> None:
        self.context, self.label = context, label
        self.generation = 0
        self.uploads = UploadCount()
        self.texture = None
        self.upload(data)

    @property
    def capacity_bytes(self) -> int:
        width, height = self.texture.size[0], self.texture.size[1]
        return width * height * TEXEL_CHANNELS * self.dtype.itemsize

    @property
    def resource(self) -> wgpu.GPUTextureView:
        return self._view

    def upload(self, data: np.ndarray, rows: np.ndarray | None = None) -> None:
        """Make the texture equal `data` (float32 or uint8 (H, W, 4)), given that only texel `rows`
        (sorted, unique) differ from the last upload; None, or a new size or type, writes every row."""
        data = np.ascontiguousarray(data)
        if data.ndim != 3 or data.shape[2] != TEXEL_CHANNELS or data.dtype not in FORMATS:
            raise ValueError(
                f"texture {self.label!r} holds (H, W, {TEXEL_CHANNELS}) float32 or uint8 texels, got {data.shape} {data.dtype}"
            )
        height, width = data.shape[:2]
        if self.texture is None or (self.texture.size[0], self.texture.size[1], self.dtype) != (
            width,
            height,
            data.dtype,
        ):
            self._allocate(width, height, data.dtype)
            rows = None
        for start, stop in [(0, height)] if rows is None else merged_runs(rows):
            self._write_rows(data, start, stop)

    def _write_rows(self, data: np.ndarray, start: int, stop: int) -> None:
        band = np.ascontiguousarray(data[start:stop])
        width = data.shape[1]
        with reporting(f"writing {band.nbytes:,} B to texture {self.label!r}"):
            self.context.device.queue.write_texture(
                {"texture": self.texture, "origin": (0, start, 0)},
                band,
                {
                    "offset": 0,
                    "bytes_per_row": width * TEXEL_CHANNELS * data.dtype.itemsize,
                    "rows_per_image": stop - start,
                },
                (width, stop - start, 1),
            )
        self.uploads.bytes += band.nbytes
        self.uploads.calls += 1

    def _allocate(self, width: int, height: int, dtype: np.dtype) -> None:
        require_float_texture(self.context, self.label, width, height)
        if self.texture is not None:
            self.texture.destroy()
        self.dtype = dtype
        with reporting(f"creating texture {self.label!r} of {width}x{height} {FORMATS[dtype]} texels"):
            self.texture = self.context.device.create_texture(
                label=self.label,
                size=(width, height, 1),
                format=FORMATS[dtype],
                usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
            )
        self._view = self.texture.create_view()
        self.generation += 1

    def destroy(self) -> None:
        self.texture.destroy()
