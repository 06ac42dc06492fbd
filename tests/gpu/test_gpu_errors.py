"""wgpu's errors come out as one-line GpuFailure errors naming what was being done (the buffer or
texture, its size) and wgpu's words: validation errors from requests beyond the device's limits
(our own checks bypassed), and every kind of work on a device that was lost."""

from __future__ import annotations

import numpy as np
import pytest
import wgpu

from wgputrace.gpu import texels as texels_module
from wgputrace.gpu.buffers import create_buffer, read_buffer, storage_buffer, write_buffer
from wgputrace.gpu.device import GpuFailure, new_context
from wgputrace.gpu.layout import TRIANGLE
from wgputrace.gpu.texels import MAX_TEXEL_ROW, TrackedTexels
from wgputrace.gpu.tracked_buffer import TrackedBuffer

pytestmark = pytest.mark.gpu

STORAGE = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST
WORDS = np.arange(4, dtype=np.uint32)
# buffer sizes are u64
U64_END = 2**64


def failure(call, *args) -> GpuFailure:
    with pytest.raises(GpuFailure) as error:
        call(*args)
    assert "\n" not in str(error.value)
    assert isinstance(error.value.__cause__, wgpu.GPUError)
    return error.value


def test_buffer_beyond_max_buffer_size_names_label_size_and_wgpu_words(gpu_context):
    size = gpu_context.device.limits["max-buffer-size"] + 4
    if size >= U64_END:
        pytest.skip("max-buffer-size is the largest u64: no larger buffer can be asked for")
    message = str(failure(create_buffer, gpu_context, "too big", size, STORAGE))
    assert message.startswith(f"creating buffer 'too big' of {size:,} B: Validation Error: ")
    assert "greater than the maximum buffer size" in message


def test_buffer_with_invalid_usage_names_label_and_size(gpu_context):
    usage = wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.STORAGE
    message = str(failure(create_buffer, gpu_context, "mappable storage", 64, usage))
    assert message.startswith("creating buffer 'mappable storage' of 64 B: Validation Error: ")


def test_texture_beyond_max_dimension_names_label_and_size(gpu_context, monkeypatch):
    tallest = gpu_context.device.limits["max-texture-dimension-2d"]
    monkeypatch.setattr(texels_module, "require_texels", lambda *args: (MAX_TEXEL_ROW, tallest + 1))
    message = str(failure(TrackedTexels, gpu_context, "too tall", TRIANGLE.zeros(3)))
    assert message.startswith(f"creating texture 'too tall' of {MAX_TEXEL_ROW}x{tallest + 1} texels (")


@pytest.fixture
def lost():
    """A device of its own with a buffer made before it was lost (destroyed: the loss we can cause)."""
    context = new_context()
    before = storage_buffer(context, "made before", WORDS, read_back=True)
    context.device.destroy()
    return context, before


def test_work_on_a_lost_device_is_a_gpu_failure_and_lost_reason_says_why(gpu_context, lost):
    context, before = lost
    # the loss wgpu-native logged ("(destroyed): Device lost", in some runs "(destroyed): (2)"),
    # or where it logged none the probe's error ("... Parent device is lost")
    assert any(word in context.lost_reason for word in ("destroyed", "lost"))
    assert gpu_context.lost_reason is None
    binding = "max-storage-buffer-binding-size"
    attempts = {
        "creating buffer 'made after' of 16 B": lambda: storage_buffer(context, "made after", WORDS),
        "creating buffer 'tracked' of 16 B": lambda: TrackedBuffer(
            context, "tracked", STORAGE, WORDS, binding_limit=binding
        ),
        "creating texture 'texels' of ": lambda: TrackedTexels(context, "texels", TRIANGLE.zeros(3)),
        "writing 16 B at byte 0 of buffer 'made before' (16 B)": lambda: write_buffer(context, before, 0, WORDS),
        "reading back 16 B of buffer 'made before'": lambda: read_buffer(context, before, np.uint32, 4),
    }
    for what, attempt in attempts.items():
        message = str(failure(attempt))
        assert message.startswith(what) and message.endswith("Parent device is lost"), message
