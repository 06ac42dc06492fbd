"""GPU memory that follows a numpy array of records and uploads only the rows that changed
(TrackedRecords), as buffers here and as texels (TrackedTexels).

Rows given as changed are merged into runs of consecutive rows, one write each. Memory is first
allocated at the size of its records; growing past the capacity reallocates with spare capacity,
so a scene being extended keeps its memory (and the bind groups pointing at it) for its next small
additions, and bumps `generation` so the owner knows to rebind. wgpu's errors name the memory.
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
# mesh, `python -m bench.big_mesh`: 67 rather than 84 scene bytes per triangle), and an edited one stays
# within this fraction of what it uses.
SPARE_FRACTION = 0.25


@dataclass
class UploadCount:
    """Host-to-GPU writes: bytes and `queue.write_buffer` calls."""

    bytes: int = 0
    calls: int = 0


class TrackedRecords:
    """GPU memory following a numpy array of records: `upload` writes only the rows given as
    changed, merged into runs, and reallocates (bumping `generation`) once the records outgrow the
    capacity. Subclasses hold the memory: `capacity_bytes`, `resource`, `destroy`,
    `_allocate(data, records)` and `_write(first_record, records)`."""

    what = "records"

    def __init__(self, context: GpuContext, label: str, data: np.ndarray, *, spare: bool) -> None:
        self.context, self.label, self.spare = context, label, spare
        self.dtype = data.dtype
        self.generation = 0
        self.uploads = UploadCount()
        self._reallocate(np.ascontiguousarray(data))

    @property
    def capacity_bytes(self) -> int:
        raise NotImplementedError

    @property
    def capacity_records(self) -> int:
        return self.capacity_bytes // self.dtype.itemsize

    def upload(self, data: np.ndarray, rows: np.ndarray | None = None) -> None:
        """Make the GPU copy equal `data`, given that only `rows` (sorted, unique) differ from the
        last upload, rows beyond the old length included; None means every row."""
        data = contiguous_records(data, self.dtype, f"{self.what} {self.label!r}")
        if len(data) > self.capacity_records:
            self._reallocate(data)
            return
        self._uploaded(data)
        for start, stop in [(0, len(data))] if rows is None else merged_runs(rows):
            self._write(start, data[start:stop])

    def _reallocate(self, data: np.ndarray) -> None:
        """New memory for `data` (with SPARE_FRACTION more records once it outgrew its first, at most
        `_most_records`), all of it written."""
        grown = self.spare and self.generation > 0
        records = len(data) + (int(np.ceil(len(data) * SPARE_FRACTION)) if grown else 0)
        self._allocate(data, max(len(data), min(records, self._most_records())))
        self.generation += 1
        self._uploaded(data)
        self._write(0, data)

    def _most_records(self) -> int:
        """The most records the adapter lets this memory hold."""
        raise NotImplementedError

    def _uploaded(self, data: np.ndarray) -> None:
        """`data` is what the GPU copy holds from now on."""

    def _count(self, nbytes: int) -> None:
        self.uploads.bytes += nbytes
        self.uploads.calls += 1


class TrackedBuffer(TrackedRecords):
    what = "buffer"

    def __init__(
        self, context: GpuContext, label: str, usage: int, data: np.ndarray, *, binding_limit: str, spare: bool = True
    ) -> None:
        self.usage, self.binding_limit = usage, binding_limit
        self.used_bytes = 0
        self.buffer = None
        super().__init__(context, label, data, spare=spare)

    @property
    def capacity_bytes(self) -> int:
        return self.buffer.size

    @property
    def resource(self) -> wgpu.GPUBuffer:
        """What a bind group binds: the buffer (TrackedTexels binds a texture view)."""
        return self.buffer

    def destroy(self) -> None:
        self.buffer.destroy()

    def _most_records(self) -> int:
        # rounded up: the spare of a buffer near its limit takes the binding's bytes to the last one
        return -(-self.context.device.limits[self.binding_limit] // self.dtype.itemsize)

    def _allocate(self, data: np.ndarray, records: int) -> None:
        require_records(self.context, self.label, len(data), data.itemsize, self.binding_limit)
        if self.buffer is not None:
            self.buffer.destroy()
        limit = self.context.device.limits[self.binding_limit]
        capacity = max(min(records * data.itemsize, limit), MIN_BUFFER_BYTES)
        self.buffer = create_buffer(self.context, self.label, capacity, self.usage)

    def _uploaded(self, data: np.ndarray) -> None:
        self.used_bytes = data.nbytes

    def _write(self, first_record: int, records: np.ndarray) -> None:
        if records.nbytes == 0:
            return
        write_buffer(self.context, self.buffer, first_record * records.itemsize, records)
        self._count(records.nbytes)


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
