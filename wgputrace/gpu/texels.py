"""Records kept in rgba32uint textures ("texels") for shaders that read them at random.

On lavapipe a random texture load costs a fraction of a storage-buffer load, so the BVH's nodes
and the triangles are read from texels: traversal, shading and light sampling alike, and no
storage buffer holds them (figures in bench/README.md's optimization log;
`python -m bench.kernel_profile --variants storage_triangles` measures the triangles' part).

A record of S bytes (gpu.layout pads every struct to a multiple of 16) is S / 16 consecutive
texels holding the bytes of its storage-buffer layout; texel t lies at column t % width and row
t // width of a texture whose width is a power of two, so the shader finds it with a mask and a
shift (`texel_at` in shaders/common/texels.wgsl) rather than a division. The WGSL loader of a struct,
`load_<Struct>(texels, index)`, is generated from its layout (`texel_loaders`), so the two cannot
drift. `TrackedTexels` follows a numpy array of records the way TrackedBuffer does: only rows
that changed are written, and once the records outgrow the texture it is reallocated with spare
capacity for the next small additions (not before: a scene as loaded costs only its records).
wgpu's errors come out as GpuFailure naming the texture (gpu/device.py `reporting`).
"""

from __future__ import annotations

import numpy as np
import wgpu

from .device import GpuContext, reporting
from .layout import TRIANGLE, WIDE_BVH_NODE, GpuStruct
from .tracked_buffer import TrackedRecords

GENERATED_TEXEL_LOADERS = "generated/texel_loaders.wgsl"
# The structs the renderer keeps in texels; the others stay in storage buffers (materials and the
# light table are read once per path vertex, not once per leaf visited). Texture size, not the
# storage binding cap, limits how many triangles fit: MAX_TEXEL_ROW x max-texture-dimension-2d
# texels, 3 per triangle (22.4 million at lavapipe's 16384 rows, against 2.8 million in its
# 128 MiB storage binding).
TEXEL_STRUCTS = (WIDE_BVH_NODE, TRIANGLE)
TEXEL_BYTES = 16
# Widest texture row, in texels (64 KiB): 8192 rows of it (WebGPU's default height limit) hold 2^25
# texels. Narrower data gets a width near the square root of its texel count, so at most one
# partly used row is wasted.
MAX_TEXEL_ROW = 4096
_SWIZZLE = "xyzw"


def texels_per_record(struct_or_dtype: GpuStruct | np.dtype) -> int:
    size = struct_or_dtype.size if isinstance(struct_or_dtype, GpuStruct) else struct_or_dtype.itemsize
    if size % TEXEL_BYTES:
        raise ValueError(f"records of {size} B do not fill whole {TEXEL_BYTES}-byte texels")
    return size // TEXEL_BYTES


def texture_shape(texel_count: int) -> tuple[int, int]:
    """(width, height) for at least `texel_count` texels: width a power of two at most
    MAX_TEXEL_ROW and at most the square root of the count, so height >= width up to that cap."""
    count = max(texel_count, 1)
    width = min(MAX_TEXEL_ROW, 1 << (int(np.sqrt(count)).bit_length() - 1))
    return width, -(-count // width)


def most_texel_records(context: GpuContext, dtype: np.dtype) -> int:
    """How many records of `dtype` the tallest texture the adapter allows holds."""
    return MAX_TEXEL_ROW * context.device.limits["max-texture-dimension-2d"] // texels_per_record(dtype)


def require_texels(context: GpuContext, label: str, record_count: int, dtype: np.dtype) -> tuple[int, int]:
    """The (width, height) of a texture of `record_count` records, or a DeviceLimitError naming the
    texture, its records, the adapter's height limit and how many records fit."""
    width, height = texture_shape(record_count * texels_per_record(dtype))
    what = f"texture {label!r} ({record_count:,} records of {dtype.itemsize} B, {width} texels a row)"
    largest = f"{most_texel_records(context, dtype):,} records"
    context.require("max-texture-dimension-2d", height, what, largest=largest)
    return width, height


def texel_loader(struct: GpuStruct) -> str:
    """WGSL `load_<name>(texels, index) -> <name>`: record `index` reassembled from its texels."""
    texel_count = texels_per_record(struct)
    lines = [
        f"fn load_{struct.name}(texels: texture_2d<u32>, index: u32) -> {struct.name} {{",
        *(f"    let t{k} = texel_at(texels, {texel_count}u * index + {k}u);" for k in range(texel_count)),
    ]
    values = []
    for (_, wgsl_type), offset in zip(struct.fields, struct.offsets, strict=True):
        components = int(wgsl_type[3]) if wgsl_type.startswith("vec") else 1
        texel, first = divmod(offset // 4, 4)
        bits = f"t{texel}.{_SWIZZLE[first : first + components]}"
        values.append(bits if wgsl_type in ("u32", f"vec{components}<u32>") else f"bitcast<{wgsl_type}>({bits})")
    lines.append(f"    return {struct.name}({', '.join(values)});")
    lines.append("}")
    return "\n".join(lines)


def texel_loaders(structs: tuple[GpuStruct, ...]) -> str:
    """The generated file GENERATED_TEXEL_LOADERS: a loader for each struct kept in texels."""
    header = "// Generated by wgputrace.gpu.texels: structs reassembled from their texels.\n"
    return header + '//! include "common/texels.wgsl"\n\n' + "\n\n".join(texel_loader(s) for s in structs) + "\n"


class TrackedTexels(TrackedRecords):
    """A texture of records following a numpy array, bound through `resource` (a texture view)."""

    what = "texture"

    def __init__(self, context: GpuContext, label: str, data: np.ndarray, *, spare: bool = True) -> None:
        self.texels_per_record = texels_per_record(data.dtype)
        self.texture = None
        super().__init__(context, label, data, spare=spare)

    @property
    def capacity_bytes(self) -> int:
        width, height = self.texture.size[0], self.texture.size[1]
        return width * height * TEXEL_BYTES

    @property
    def resource(self) -> wgpu.GPUTextureView:
        return self._view

    def destroy(self) -> None:
        self.texture.destroy()

    def _most_records(self) -> int:
        # spare only as far as the tallest texture allowed: records that fit must not be refused
        # for want of room for the next additions
        return most_texel_records(self.context, self.dtype)

    def _allocate(self, data: np.ndarray, records: int) -> None:
        width, height = require_texels(self.context, self.label, records, self.dtype)
        if self.texture is not None:
            self.texture.destroy()
        size = f"{width}x{height} texels ({width * height * TEXEL_BYTES:,} B)"
        with reporting(f"creating texture {self.label!r} of {size}"):
            self.texture = self.context.device.create_texture(
                label=self.label,
                size=(width, height, 1),
                format=wgpu.TextureFormat.rgba32uint,
                # COPY_SRC: what was uploaded can be read back and checked against the host records
                usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST | wgpu.TextureUsage.COPY_SRC,
            )
        self._view = self.texture.create_view()

    def _write(self, first_record: int, records: np.ndarray) -> None:
        """Write records starting at `first_record`: a run spanning texture rows is at most three
        rectangles (the end of its first row, whole rows, the start of its last row)."""
        if records.size == 0:
            return
        texels = np.frombuffer(records.tobytes(), np.uint32).reshape(-1, 4)
        width = self.texture.size[0]
        start = first_record * self.texels_per_record
        done = 0
        while done < len(texels):
            row, column = divmod(start + done, width)
            if column or len(texels) - done < width:
                count, rows = min(width - column, len(texels) - done), 1
            else:
                count, rows = width, (len(texels) - done) // width
            block = texels[done : done + count * rows]
            with reporting(f"writing {block.nbytes:,} B at texel ({column}, {row}) of texture {self.label!r}"):
                self.context.device.queue.write_texture(
                    {"texture": self.texture, "origin": (column, row, 0)},
                    block,
                    {"offset": 0, "bytes_per_row": count * TEXEL_BYTES, "rows_per_image": rows},
                    (count, rows, 1),
                )
            self._count(block.nbytes)
            done += count * rows
