"""Tracked buffers: changed rows become merged write_buffer calls, the GPU copy equals the host
array afterwards, a first allocation is exact, outgrowing it reallocates with spare capacity, and
that spare absorbs the next small growth."""

from __future__ import annotations

import numpy as np
import pytest
import wgpu

from wgputrace.gpu.buffers import read_buffer
from wgputrace.gpu.device import DeviceLimitError
from wgputrace.gpu.layout import TRIANGLE
from wgputrace.gpu.tracked_buffer import SPARE_FRACTION, TrackedBuffer, merged_runs

USAGE = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC
LIMIT = "max-storage-buffer-binding-size"


def records(rng, count: int) -> np.ndarray:
    data = TRIANGLE.zeros(count)
    data["v0"] = rng.normal(size=(count, 3))
    data["material"] = rng.integers(0, 100, count)
    return data


def extended(data: np.ndarray, extra: np.ndarray) -> np.ndarray:
    """data followed by extra, keeping the padded GPU dtype (np.concatenate would pack it)."""
    joined = TRIANGLE.zeros(len(data) + len(extra))
    joined[: len(data)], joined[len(data) :] = data, extra
    return joined


def on_gpu(context, buffer: TrackedBuffer, count: int) -> np.ndarray:
    return read_buffer(context, buffer.buffer, TRIANGLE.dtype, count)


def test_merged_runs():
    assert merged_runs(np.array([1, 2, 3, 7, 9, 10])) == [(1, 4), (7, 8), (9, 11)]
    assert merged_runs(np.array([], np.int64)) == []


def test_changed_rows_upload_as_merged_runs(gpu_context, rng):
    data = records(rng, 100)
    buffer = TrackedBuffer(gpu_context, "test", USAGE, data, binding_limit=LIMIT)
    assert buffer.uploads.calls == 1 and buffer.uploads.bytes == data.nbytes
    assert buffer.capacity_bytes == data.nbytes  # no spare until the records outgrow their buffer
    buffer.uploads.calls = buffer.uploads.bytes = 0
    rows = np.array([3, 4, 5, 50, 98, 99])
    data[rows] = records(rng, len(rows))
    buffer.upload(data, rows)
    assert (buffer.uploads.calls, buffer.uploads.bytes) == (3, len(rows) * TRIANGLE.size)
    np.testing.assert_array_equal(on_gpu(gpu_context, buffer, 100), data)


def test_growth_reallocates_with_spare_that_holds_the_next_growth(gpu_context, rng):
    data = records(rng, 40)
    buffer = TrackedBuffer(gpu_context, "test", USAGE, data, binding_limit=LIMIT)
    generation, gpu_buffer = buffer.generation, buffer.buffer
    grown = extended(data, records(rng, 8))
    buffer.upload(grown, np.arange(40, 48))
    assert buffer.buffer is not gpu_buffer and buffer.generation == generation + 1
    spare = int(np.ceil(48 * SPARE_FRACTION))
    assert buffer.capacity_bytes == (48 + spare) * TRIANGLE.size
    np.testing.assert_array_equal(on_gpu(gpu_context, buffer, 48), grown)
    generation, gpu_buffer = buffer.generation, buffer.buffer
    filled = extended(grown, records(rng, spare))
    buffer.upload(filled, np.arange(48, 48 + spare))
    assert buffer.buffer is gpu_buffer and buffer.generation == generation
    np.testing.assert_array_equal(on_gpu(gpu_context, buffer, 48 + spare), filled)
    larger = extended(filled, records(rng, 1))
    buffer.upload(larger, np.arange(48 + spare, 49 + spare))
    assert buffer.buffer is not gpu_buffer and buffer.generation == generation + 1
    np.testing.assert_array_equal(on_gpu(gpu_context, buffer, 49 + spare), larger)


def test_a_buffer_beyond_the_binding_limit_names_limit_and_adapter_value(gpu_context, rng, monkeypatch):
    monkeypatch.setitem(gpu_context.device.limits, LIMIT, 1024)
    with pytest.raises(
        DeviceLimitError,
        match=r"'test' \(22 records of 48 B\) needs max-storage-buffer-binding-size = 1,056 but the adapter .* offers 1,024",
    ):
        TrackedBuffer(gpu_context, "test", USAGE, records(rng, 22), binding_limit=LIMIT)
    # spare capacity never exceeds the limit: growing to 21 rows fits, their spare does not
    data = records(rng, 20)
    buffer = TrackedBuffer(gpu_context, "test", USAGE, data, binding_limit=LIMIT)
    buffer.upload(extended(data, records(rng, 1)), np.arange(20, 21))
    assert buffer.capacity_bytes == 1024


def test_records_of_another_layout_are_refused(gpu_context, rng):
    data = records(rng, 4)
    buffer = TrackedBuffer(gpu_context, "test", USAGE, data, binding_limit=LIMIT)
    packed = np.concatenate([data, data])  # numpy packs padded structured dtypes: 40-byte rows
    with pytest.raises(ValueError, match="'test' holds records of 48 B, got 40 B"):
        buffer.upload(packed)
