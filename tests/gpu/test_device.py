"""The device module: one device, limits checked with messages naming the limit and both values."""

from __future__ import annotations

import pytest

from wgputrace.gpu.device import DeviceLimitError, describe, gpu


def test_one_device_per_process(gpu_context):
    assert gpu() is gpu_context


def test_limit_error_names_limit_and_values(gpu_context):
    limit = gpu_context.device.limits["max-storage-buffer-binding-size"]
    with pytest.raises(DeviceLimitError) as error:
        gpu_context.require("max-storage-buffer-binding-size", limit + 4, "buffer 'triangles'")
    message = str(error.value)
    assert "max-storage-buffer-binding-size" in message
    assert f"{limit + 4:,}" in message and f"{limit:,}" in message
    assert "triangles" in message


def test_describe_reports_adapter_and_limits(gpu_context):
    info = describe()
    assert info["adapter"] and info["backend"]
    assert info["limits"]["max-storage-buffer-binding-size"] > 0
