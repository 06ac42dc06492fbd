"""Render pipelines (their layouts from `BindGroup`s) and textures: what presenting to a window
needs besides compute kernels, with the same include mechanism and compile errors naming files."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import wgpu

from .bindings import BindGroup
from .device import GpuContext
from .kernel import Kernel, compile_shader

# copy_texture_to_buffer writes rows at a multiple of this many bytes.
_COPY_ROW_ALIGNMENT = 256


class RenderKernel(Kernel):
    """A render pipeline (`vertex_main`, `fragment_main`) drawing to `target_format`, and its groups."""

    def __init__(
        self,
        context: GpuContext,
        entry: str,
        target_format: str,
        groups: Sequence[BindGroup],
        *,
        generated: dict[str, str] | None = None,
        constants: dict[str, float | int | bool] | None = None,
        topology: str = "triangle-list",
        label: str | None = None,
    ) -> None:
        label = label or entry
        constants = constants or {}

        def create(module, layout):
            return context.device.create_render_pipeline(
                label=label,
                layout=layout,
                vertex={"module": module, "entry_point": "vertex_main", "buffers": [], "constants": constants},
                primitive={"topology": topology},
                fragment={
                    "module": module,
                    "entry_point": "fragment_main",
                    "targets": [{"format": target_format}],
                    "constants": constants,
                },
            )

        source, self.pipeline = compile_shader(context, entry, groups, generated, label, create)
        super().__init__(context, source, groups, label)


def rgba8_texture(context: GpuContext, label: str, width: int, height: int) -> wgpu.GPUTexture:
    """An rgba8unorm texture shaders read and the host writes (the viewer's text overlay)."""
    return context.device.create_texture(
        label=label,
        size=(width, height, 1),
        format="rgba8unorm",
        usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
    )


def write_rgba8(context: GpuContext, texture: wgpu.GPUTexture, pixels: np.ndarray) -> None:
    """Upload (height, width, 4) uint8 pixels into `texture`, which has that size."""
    pixels = np.ascontiguousarray(pixels, dtype=np.uint8)
    height, width = pixels.shape[:2]
    context.device.queue.write_texture(
        {"texture": texture}, pixels, {"bytes_per_row": width * 4, "rows_per_image": height}, (width, height, 1)
    )


def write_image(context: GpuContext, texture: wgpu.GPUTexture, image: np.ndarray) -> None:
    """Upload a linear (height, width, 3) image into the top-left of an rgba32float `texture`
    (alpha 1): a picture made on the host (OIDN's, render_frame's) shown as the resolved one is."""
    height, width, _ = image.shape
    texels = np.ones((height, width, 4), np.float32)
    texels[:, :, :3] = image
    context.device.queue.write_texture(
        {"texture": texture}, texels, {"bytes_per_row": width * texels.itemsize * 4}, (width, height, 1)
    )


def target_texture(context: GpuContext, label: str, width: int, height: int, target_format: str) -> wgpu.GPUTexture:
    """A texture to draw into and read back (screenshots), the same format as the window's."""
    return context.device.create_texture(
        label=label,
        size=(width, height, 1),
        format=target_format,
        usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC,
    )


def image_texture(context: GpuContext, label: str, width: int, height: int, texture_format: str) -> wgpu.GPUTexture:
    """A texture kernels write (storage) and later kernels read (textureLoad), copyable both ways:
    the viewer's per-pixel images. Reads through textures are several times faster than through
    storage buffers on CPU adapters (why `TrackedTexels` exists)."""
    usage = (
        wgpu.TextureUsage.STORAGE_BINDING
        | wgpu.TextureUsage.TEXTURE_BINDING
        | wgpu.TextureUsage.COPY_SRC
        | wgpu.TextureUsage.COPY_DST
    )
    return context.device.create_texture(label=label, size=(width, height, 1), format=texture_format, usage=usage)


def copy_texture(context: GpuContext, source: wgpu.GPUTexture, target: wgpu.GPUTexture, size: tuple[int, int]) -> None:
    """The top-left `size` pixels of `source` into `target` (same format)."""
    encoder = context.device.create_command_encoder()
    encoder.copy_texture_to_texture({"texture": source}, {"texture": target}, (size[0], size[1], 1))
    context.submit(encoder, f"a copy of texture {source.label!r}")


def read_texture(
    context: GpuContext, texture: wgpu.GPUTexture, dtype: np.dtype, channels: int, size: tuple[int, int] | None = None
) -> np.ndarray:
    """The top-left `size` (default: all) texels as (height, width, channels) of `dtype`."""
    width, height = size or (texture.size[0], texture.size[1])
    texel_bytes = np.dtype(dtype).itemsize * channels
    row_bytes = -(-width * texel_bytes // _COPY_ROW_ALIGNMENT) * _COPY_ROW_ALIGNMENT
    buffer = context.device.create_buffer(
        size=row_bytes * height, usage=wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.MAP_READ
    )
    encoder = context.device.create_command_encoder()
    encoder.copy_texture_to_buffer(
        {"texture": texture},
        {"buffer": buffer, "bytes_per_row": row_bytes, "rows_per_image": height},
        (width, height, 1),
    )
    context.submit(encoder, f"a read-back of texture {texture.label!r}")
    buffer.map_sync(wgpu.MapMode.READ)
    rows = np.frombuffer(buffer.read_mapped(), np.uint8).reshape(height, row_bytes)[:, : width * texel_bytes].copy()
    buffer.unmap()
    buffer.destroy()
    return rows.view(dtype).reshape(height, width, channels)
