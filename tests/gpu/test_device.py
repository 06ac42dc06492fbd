"""The device module: one device, also when two threads ask first at once, made again once lost;
limits checked with messages naming the limit and both values."""

from __future__ import annotations

import threading

import pytest

from wgputrace.gpu import device
from wgputrace.gpu.device import DeviceLimitError, describe, gpu, new_context


def test_one_device_per_process(gpu_context):
    assert gpu() is gpu_context


@pytest.mark.gpu
def test_two_threads_asking_first_get_one_device(monkeypatch):
    monkeypatch.setattr(device, "_context", None)
    made = []

    def counted_new_context():
        made.append(new_context())
        return made[-1]

    monkeypatch.setattr(device, "new_context", counted_new_context)
    both_ready = threading.Barrier(2)
    contexts = [None, None]

    def ask(index: int) -> None:
        both_ready.wait()
        contexts[index] = gpu()

    threads = [threading.Thread(target=ask, args=(index,)) for index in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(made) == 1
    assert contexts[0] is contexts[1] is made[0]


@pytest.mark.gpu
def test_a_lost_device_is_replaced(monkeypatch):
    """What the viewer relies on to recreate its renderer after a device loss."""
    lost = new_context()
    monkeypatch.setattr(device, "_context", lost)
    assert gpu() is lost and lost.lost_reason is None
    lost.device.destroy()
    replacement = gpu()
    assert lost.lost_reason is not None
    assert replacement is not lost and replacement.lost_reason is None
    assert gpu() is replacement


def test_limit_error_names_limit_and_values(gpu_context):
    limit = gpu_context.device.limits["max-storage-buffer-binding-size"]
    with pytest.raises(DeviceLimitError) as error:
        gpu_context.require("max-storage-buffer-binding-size", limit + 4, "buffer 'triangles'")
    message = str(error.value)
    assert "max-storage-buffer-binding-size" in message
    assert f"{limit + 4:,}" in message and f"{limit:,}" in message
    assert "triangles" in message


def test_limit_error_says_what_the_limit_allows(gpu_context):
    with pytest.raises(DeviceLimitError, match=r"offers [\d,]+ \(12 records at most\)$"):
        gpu_context.require("max-texture-dimension-2d", 10**9, "texture 'nodes'", largest="12 records")


def test_describe_reports_adapter_and_limits(gpu_context):
    info = describe()
    assert info["adapter"] and info["backend"]
    assert info["limits"]["max-storage-buffer-binding-size"] > 0


def test_flat_list_beyond_llvmpipe_loop_budget_per_path_is_refused(gpu_context):
    """llvmpipe silently ends loops once an invocation ran 65,535 iterations of all its loops
    together: a flat list whose paths (two rays per vertex, every triangle tested by each) could
    pass that would miss geometry, so the renderer refuses it with a message naming the limit."""
    import numpy as np

    from wgputrace import Diffuse, Renderer, Scene, Shape

    limit = gpu_context.loop_iteration_limit
    if limit is None:
        pytest.skip("this adapter has no loop iteration limit (Mesa 22's llvmpipe has one, Mesa 25's none)")
    max_depth = 3
    allowed = limit // (2 * max_depth)
    corners = np.random.default_rng(1).uniform(-1, 1, (allowed + 1, 3, 3)).astype(np.float32)
    with pytest.raises(DeviceLimitError, match=f"per path of max depth 3, .* ends shader loops after {limit:,}"):
        Renderer(Scene([Shape("soup", corners, Diffuse("grey"))]), 8, 8, accel="flat", max_depth=max_depth)
    Renderer(Scene([Shape("soup", corners[:allowed], Diffuse("grey"))]), 8, 8, accel="flat", max_depth=max_depth)
