"""Storage and uniform buffers created from numpy arrays, and read back into them.

wgpu's errors while creating, filling or reading a buffer come out as GpuFailure naming the buffer
and its size (`reporting`)."""

from __future__ import annotations

import numpy as np
import wgpu

from .device import GpuContext, reporting

# wgpu buffers may not be empty, and writes must cover a multiple of 4 bytes.
MIN_BUFFER_BYTES = 16


def create_buffer(context: GpuContext, label: str, size: int, usage: int) -> wgpu.GPUBuffer:
    """An uninitialised buffer of `size` bytes (callers check the device's limits first)."""
    with reporting(f"creating buffer {label!r} of {size:,} B"):
        return context.device.create_buffer(label=label, size=size, usage=usage)


def write_buffer(context: GpuContext, buffer: wgpu.GPUBuffer, offset: int, data: np.ndarray) -> None:
    """`queue.write_buffer` of `data` at byte `offset`."""
    with reporting(f"writing {data.nbytes:,} B at byte {offset:,} of buffer {buffer.label!r} ({buffer.size:,} B)"):
        context.device.queue.write_buffer(buffer, offset, data)


def storage_buffer(context: GpuContext, label: str, data: np.ndarray, *, read_back: bool = False) -> wgpu.GPUBuffer:
    """A storage buffer holding `data` (any contiguous array; structured dtypes from gpu.layout)."""
    data = np.ascontiguousarray(data)
    context.require("max-storage-buffer-binding-size", data.nbytes, f"buffer {label!r}")
    usage = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST
    if read_back:
        usage |= wgpu.BufferUsage.COPY_SRC
    buffer = create_buffer(context, label, max(data.nbytes, MIN_BUFFER_BYTES), usage)
    if data.nbytes:
        write_buffer(context, buffer, 0, data)
    return buffer


# Parameter structs (UNIFORM bindings) are bound as read-only storage: UNIFORM's comment says why.
PARAMETER_USAGE = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST
PARAMETER_BINDING_LIMIT = "max-storage-buffer-binding-size"


def uniform_buffer(context: GpuContext, label: str, data: np.ndarray) -> wgpu.GPUBuffer:
    """A buffer for a parameter struct (a UNIFORM binding) holding `data`."""
    data = np.ascontiguousarray(data)
    context.require(PARAMETER_BINDING_LIMIT, data.nbytes, f"parameters {label!r}")
    buffer = create_buffer(context, label, max(data.nbytes, MIN_BUFFER_BYTES), PARAMETER_USAGE)
    write_buffer(context, buffer, 0, data)
    return buffer


def read_buffer(context: GpuContext, buffer: wgpu.GPUBuffer, dtype: np.dtype, count: int) -> np.ndarray:
    size = count * np.dtype(dtype).itemsize
    with reporting(f"reading back {size:,} B of buffer {buffer.label!r}"):
        raw = context.device.queue.read_buffer(buffer, 0, size)
    return np.frombuffer(raw, dtype=dtype, count=count).copy()
