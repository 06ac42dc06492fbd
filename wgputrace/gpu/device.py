"""The one place that owns the wgpu adapter and device.

One device per process, created on first use with the adapter's own maxima for the limits a path
tracer needs (some wgpu implementations default lower than what the hardware offers). Scenes
check their needs against these limits and fail with a message naming the limit and both values.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass

import wgpu

# The limits our buffers and dispatches depend on; `wgputrace info` prints these.
LIMITS_WE_USE = (
    "max-storage-buffer-binding-size",
    "max-buffer-size",
    "max-uniform-buffer-binding-size",
    "max-compute-workgroups-per-dimension",
    "max-compute-invocations-per-workgroup",
    "max-storage-buffers-per-shader-stage",
    # texture rows: how many triangles and BVH nodes fit (gpu/texels.py)
    "max-texture-dimension-2d",
)


_FENCE_BYTES = 4

# llvmpipe (Mesa's CPU driver) gives an invocation one budget of this many loop iterations, shared
# by all its loops (nested or one after another) and by the 8 invocations it runs in lockstep, and
# silently ends every loop once it is spent; measured here with Mesa 22.3
# (tests/shaders/test_loop_budget.py). shaders/loop_budget.wgsl tells a shader when it happened.
LLVMPIPE_LOOP_ITERATION_LIMIT = 65_535


class DeviceLimitError(RuntimeError):
    """The scene or image needs more than the adapter offers."""


@dataclass(frozen=True)
class GpuContext:
    adapter: wgpu.GPUAdapter
    device: wgpu.GPUDevice
    # A few bytes to read back: reading waits for all submitted work. (wgpu-py 0.32's
    # queue.on_submitted_work_done_sync fails with a cffi callback type error.)
    fence: wgpu.GPUBuffer

    def finish(self) -> None:
        """Block until every command submitted so far has run."""
        self.device.queue.read_buffer(self.fence, 0, _FENCE_BYTES)

    @property
    def adapter_name(self) -> str:
        info = self.adapter.info
        return f"{info['device']} ({info['backend_type']}, {info['adapter_type']})"

    @property
    def loop_iteration_limit(self) -> int | None:
        """Loop iterations after which the driver silently ends an invocation's loops (all of them
        together); None where there is no such budget."""
        return LLVMPIPE_LOOP_ITERATION_LIMIT if "llvmpipe" in self.adapter.info["device"] else None

    def require(self, limit: str, needed: int, what: str) -> None:
        available = self.device.limits[limit]
        if needed > available:
            raise DeviceLimitError(
                f"{what} needs {limit} = {needed:,} but the adapter {self.adapter_name} offers {available:,}"
            )


_context: GpuContext | None = None


def _quiet_runtime_dir() -> None:
    # Mesa's Vulkan WSI warns on every process start when XDG_RUNTIME_DIR is unset; a private
    # empty directory is all it asks for.
    if not os.environ.get("XDG_RUNTIME_DIR"):
        os.environ["XDG_RUNTIME_DIR"] = tempfile.mkdtemp(prefix="wgputrace-xdg-")


def gpu() -> GpuContext:
    """The process-wide adapter and device, created on first call."""
    global _context
    if _context is None:
        _quiet_runtime_dir()
        adapter = wgpu.gpu.request_adapter_sync(power_preference="high-performance")
        if adapter is None:
            raise RuntimeError("wgpu found no adapter; on Debian install mesa-vulkan-drivers for a CPU fallback")
        wanted = {name: adapter.limits[name] for name in LIMITS_WE_USE}
        features = [f for f in ("timestamp-query",) if f in adapter.features]
        device = adapter.request_device_sync(required_limits=wanted, required_features=features)
        fence = device.create_buffer(label="fence", size=_FENCE_BYTES, usage=wgpu.BufferUsage.COPY_SRC)
        _context = GpuContext(adapter, device, fence)
    return _context


def describe() -> dict:
    """Adapter, backend and the limits that matter to us, for `wgputrace info` and bench files."""
    context = gpu()
    info = context.adapter.info
    return {
        "adapter": info["device"],
        "description": info["description"],
        "vendor": info["vendor"],
        "adapter_type": info["adapter_type"],
        "backend": info["backend_type"],
        "wgpu": wgpu.__version__,
        "limits": {name: context.device.limits[name] for name in LIMITS_WE_USE},
    }
