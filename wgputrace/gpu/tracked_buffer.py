"""GPU buffers that follow a numpy array of records and upload only the rows that changed.

Rows given as changed are merged into runs of consecutive rows, and each run is one
`queue.write_buffer`. A buffer is first allocated at the size of its records; growing past the
capacity reallocates with spare capacity, so a scene that is being extended keeps its buffer (and
the bind groups that point at it) for its next small additions, uploads everything, and bumps
`generation` so the owner knows to rebind. wgpu's errors come out as GpuFailure naming the buffer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from .buffers import MIN_BUFFER_BYTES, create_buffer, write_buffer
from .device import GpuContext

# Headroom allocated beyond the current size, as a fraction of it, once records have outgrown their
# buffer: a few more added shapes then fit without reallocating. Not on the first allocation, so a
# scene as loaded costs only its records (triangles: 48 rather than 60 bytes each; a million-triangle
# mesh, bench/big_mesh.py: 67 rather than 84 scene bytes per triangle), and an edited one stays
# within this fraction of what it uses.
SPARE_FRACTION = 0.25


@dataclass
class UploadCount:
    """Host-to-GPU writes: bytes and `queue.write_buffer` calls."""

    bytes: int = 0
    calls: int = 0


class TrackedBuffer:
    def __init__(
        self, context: GpuContext, label: str, usage: int, data: np.ndarray, *, binding_limit: str, spare: bool = True
    ) -> None:
        self.context, self.label, self.usage = context, label, usage
        self.binding_limit, self.spare = binding_limit, spare
        self.generation = 0
        self.uploads = UploadCount()
        self.used_bytes = 0
        self.buffer = None
        self.dtype = data.dtype
        self._allocate(np.ascontiguousarray(data))

    @property
    def capacity_bytes(self) -> int:
        return self.buffer.size

    @property
    def resource(self) -> wgpu.GPUBuffer:
        """What a bind group binds: the buffer (TrackedTexels binds a texture view)."""
        return self.buffer

    def destroy(self) -> None:
        self.buffer.destroy()

    def upload(self, data: np.ndarray, rows: np.ndarray | None = None) -> None:
        """Make the GPU copy equal `data`, given that only `rows` (sorted, unique) differ from the
        last upload, rows beyond the old length included; None means every row."""
        data = contiguous_records(data, self.dtype, f"buffer {self.label!r}")
        if data.nbytes > self.buffer.size:
            self._allocate(data)
            return
        self.used_bytes = data.nbytes
        if rows is None:
            self._write(0, data)
            return
        for start, stop in merged_runs(rows):
            self._write(start * data.itemsize, data[start:stop])

    def _allocate(self, data: np.ndarray) -> None:
        require_records(self.context, self.label, len(data), data.itemsize, self.binding_limit)
        capacity = data.nbytes
        if self.spare and self.buffer is not None:
            spare_rows = int(np.ceil(len(data) * SPARE_FRACTION))
            capacity = min(data.nbytes + spare_rows * data.itemsize, self.context.device.limits[self.binding_limit])
        if self.buffer is not None:
            self.buffer.destroy()
        self.buffer = create_buffer(self.context, self.label, max(capacity, MIN_BUFFER_BYTES), self.usage)
        self.generation += 1
        self.used_bytes = data.nbytes
        self._write(0, data)

    def _write(self, offset: int, data: np.ndarray) -> None:
        if data.nbytes == 0:
            return
        write_buffer(self.context, self.buffer, offset, data)
        self.uploads.bytes += data.nbytes
        self.uploads.calls += 1


def require_records(context: GpuContext, label: str, record_count: int, record_bytes: int, binding_limit: str) -> None:
    """DeviceLimitError unless a buffer of `record_count` records fits both the binding limit and
    the buffer size limit, naming the buffer, the limit and how many records it allows."""
    what = f"buffer {label!r} ({record_count:,} records of {record_bytes} B)"
    for limit in (binding_limit, "max-buffer-size"):
        largest = f"{context.device.limits[limit] // record_bytes:,} records"
        context.require(limit, record_count * record_bytes, what, largest=largest)


def contiguous_records(data: np.ndarray, dtype: np.dtype, holder: str) -> np.ndarray:
    """`data` as a contiguous array, refused unless its records are `dtype` (what `holder` holds)."""
    data = np.ascontiguousarray(data)
    if data.dtype != dtype:
        # np.concatenate of padded structured records silently packs them (numpy 2)
        raise ValueError(f"{holder} holds records of {dtype.itemsize} B, got {data.dtype.itemsize} B: {data.dtype}")
    return data


def merged_runs(rows: np.ndarray) -> list[tuple[int, int]]:
    """Sorted unique row indices as half-open runs of consecutive rows: [1, 2, 3, 7] -> [(1, 4), (7, 8)]."""
    rows = np.asarray(rows, np.int64)
    if rows.size == 0:
        return []
    breaks = np.flatnonzero(np.diff(rows) != 1) + 1
    starts = rows[np.concatenate([[0], breaks])]
    stops = rows[np.concatenate([breaks - 1, [rows.size - 1]])] + 1
    return list(zip(starts.tolist(), stops.tolist(), strict=True))
