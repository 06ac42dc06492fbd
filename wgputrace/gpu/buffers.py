"""Storage and uniform buffers created from numpy arrays, and read back into them."""

from __future__ import annotations

import numpy as np
import wgpu

from .device import GpuContext

# wgpu buffers may not be empty, and writes must cover a multiple of 4 bytes.
MIN_BUFFER_BYTES = 16


def storage_buffer(context: GpuContext, label: str, data: np.ndarray, *, read_back: bool = False) -> wgpu.GPUBuffer:
    """A storage buffer holding `data` (any contiguous array; structured dtypes from gpu.layout)."""
    data = np.ascontiguousarray(data)
    context.require("max-storage-buffer-binding-size", data.nbytes, f"buffer {label!r}")
    usage = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST
    if read_back:
        usage |= wgpu.BufferUsage.COPY_SRC
    buffer = context.device.create_buffer(label=label, size=max(data.nbytes, MIN_BUFFER_BYTES), usage=usage)
    if data.nbytes:
        context.device.queue.write_buffer(buffer, 0, data)
    return buffer


def uniform_buffer(context: GpuContext, label: str, data: np.ndarray) -> wgpu.GPUBuffer:
    data = np.ascontiguousarray(data)
    context.require("max-uniform-buffer-binding-size", data.nbytes, f"uniform {label!r}")
    buffer = context.device.create_buffer(
        label=label, size=data.nbytes, usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST
    )
    context.device.queue.write_buffer(buffer, 0, data)
    return buffer


def read_buffer(context: GpuContext, buffer: wgpu.GPUBuffer, dtype: np.dtype, count: int) -> np.ndarray:
    raw = context.device.queue.read_buffer(buffer, 0, count * np.dtype(dtype).itemsize)
    return np.frombuffer(raw, dtype=dtype, count=count).copy()
