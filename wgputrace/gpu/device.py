"""The one place that owns the wgpu adapter and device.

One device per process, created on first use with the adapter's own maxima for the limits a path
tracer needs (some wgpu implementations default lower than the hardware offers); scenes check
their needs against them and fail naming the limit and both values. wgpu-py 0.32 raises a call's
validation and out-of-memory errors with wgpu-native's multi-line message (no error scopes), which
`reporting` makes one line; a lost device is only logged, so `GpuContext.lost_reason` probes it,
and `gpu()` makes a new device once the one it handed out is lost.
"""

from __future__ import annotations

import logging
import os
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import wgpu

# The limits our buffers and dispatches depend on; `wgputrace info` prints these.
LIMITS_WE_USE = (
    "max-storage-buffer-binding-size",
    "max-buffer-size",
    "max-uniform-buffer-binding-size",
    "max-compute-workgroups-per-dimension",
    "max-compute-invocations-per-workgroup",
    "max-storage-buffers-per-shader-stage",
    # texture rows: how many triangles and BVH nodes fit (`TrackedTexels`); the environment map's size
    "max-texture-dimension-2d",
    # the lights group sits at index 4 (`lights_group`)
    "max-bind-groups",
)


_FENCE_BYTES = 4

# llvmpipe (Mesa's CPU driver) gives an invocation one budget of this many loop iterations, shared
# by all its loops (nested or one after another) and by the 8 invocations it runs in lockstep, and
# silently ends every loop once it is spent (Mesa 22.3; the shaders' `test_loop_budget` measures it).
# `loop_budget_spent` tells a shader when it happened. Mesa 25.0 has no such budget: `_LOOP_PROBE`
# asks the driver.
LLVMPIPE_LOOP_ITERATION_LIMIT = 65_535

# A loop that must run 2 x LLVMPIPE_LOOP_ITERATION_LIMIT times, its trip count read from memory so
# that it cannot be folded; it writes how often it ran.
_LOOP_PROBE = """
@group(0) @binding(0) var<storage, read_write> trips: array<u32, 2>;
@compute @workgroup_size(1)
fn main() {
    var runs = 0u;
    loop {
        if runs >= trips[0] {
            break;
        }
        runs++;
    }
    trips[1] = runs;
}
"""


class DeviceLimitError(RuntimeError):
    """The scene or image needs more than the adapter offers."""


class GpuFailure(RuntimeError):
    """wgpu refused or lost work: a validation or out-of-memory error, or a lost device. The message
    is one line: what was being done (which buffer, its size) and wgpu's words."""


def one_line(message: str) -> str:
    """wgpu-native's multi-line error text on one line: "Validation Error: In wgpuDeviceCreateBuffer,
    label = 'x': Buffer size ... is greater than ..."."""
    lines = (line.strip() for line in message.splitlines())
    return ": ".join(line for line in lines if line and line != "Caused by:")


@contextmanager
def reporting(what: str) -> Iterator[None]:
    """wgpu errors raised inside become a GpuFailure saying `what` was being done."""
    try:
        yield
    except wgpu.GPUError as error:
        raise GpuFailure(f"{what}: {one_line(error.message)}") from error


class _DeviceLossLog(logging.Filter):
    """Keeps the reason of the last device loss wgpu-py logged, and lets the record through."""

    PREFIX = "The WGPU device was lost"

    def __init__(self) -> None:
        super().__init__()
        self.reason: str | None = None

    def filter(self, record: logging.LogRecord) -> bool:
        message = record.getMessage()
        if message.startswith(self.PREFIX):
            self.reason = one_line(message[len(self.PREFIX) :].strip())
        return True


# The log does not say which device was lost: lost_reason only gives it for a device that fails.
_device_losses = _DeviceLossLog()
logging.getLogger("wgpu").addFilter(_device_losses)


@dataclass(frozen=True)
class GpuContext:
    adapter: wgpu.GPUAdapter
    device: wgpu.GPUDevice
    # A few bytes to read back: reading waits for all submitted work. (wgpu-py 0.32's
    # queue.on_submitted_work_done_sync fails with a cffi callback type error.)
    fence: wgpu.GPUBuffer

    def finish(self) -> None:
        """Block until every command submitted so far has run."""
        with reporting("waiting for the GPU to finish"):
            self.device.queue.read_buffer(self.fence, 0, _FENCE_BYTES)

    def submit(self, encoder: wgpu.GPUCommandEncoder, what: str) -> None:
        """Finish `encoder` and submit it, after making sure the device lives: wgpu-native aborts the
        process (SIGABRT) on a submit to a lost device, where every other call raises "Parent device is
        lost".
        """
        with reporting(f"encoding {what}"):
            commands = encoder.finish()
        lost = self.lost_reason
        if lost is not None:
            raise GpuFailure(f"submitting {what}: the device was lost: {lost}")
        with reporting(f"submitting {what}"):
            self.device.queue.submit([commands])

    @property
    def lost_reason(self) -> str | None:
        """Why the device was lost ("(destroyed): Device lost", the driver's words), or None while it
        works. wgpu-py only logs a loss (`device.lost_async` is not implemented), so this asks the device
        for a tiny buffer: a device that cannot make one is gone.
        """
        try:
            self.device.create_buffer(label="lost probe", size=_FENCE_BYTES, usage=wgpu.BufferUsage.COPY_DST).destroy()
        except wgpu.GPUError as error:
            return _device_losses.reason or one_line(error.message)
        return None

    @property
    def shares_host_memory(self) -> bool:
        """Whether the adapter's buffers are allocated from host memory (lavapipe, integrated GPUs),
        so that GPU allocations count against the host's memory too."""
        return self.adapter.info["adapter_type"] in ("CPU", "IntegratedGPU")

    @property
    def adapter_name(self) -> str:
        info = self.adapter.info
        return f"{info['device']} ({info['backend_type']}, {info['adapter_type']})"

    @property
    def has_subgroups(self) -> bool:
        """Whether kernels may use subgroup operations (wgpu-native's "subgroup" feature)."""
        return "subgroup" in self.device.features

    @cached_property
    def loop_iteration_limit(self) -> int | None:
        """Loop iterations after which the driver silently ends an invocation's loops (all of them
        together); None where there is no such budget. llvmpipe is asked once (`_LOOP_PROBE`)."""
        if "llvmpipe" not in self.adapter.info["device"]:
            return None
        wanted = 2 * LLVMPIPE_LOOP_ITERATION_LIMIT
        trips = self.device.create_buffer_with_data(
            data=np.array([wanted, 0], np.uint32), usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC
        )
        pipeline = self.device.create_compute_pipeline(
            layout="auto", compute={"module": self.device.create_shader_module(code=_LOOP_PROBE), "entry_point": "main"}
        )
        entries = [{"binding": 0, "resource": {"buffer": trips}}]
        group = self.device.create_bind_group(layout=pipeline.get_bind_group_layout(0), entries=entries)
        encoder = self.device.create_command_encoder()
        probe = encoder.begin_compute_pass()
        probe.set_pipeline(pipeline)
        probe.set_bind_group(0, group)
        probe.dispatch_workgroups(1)
        probe.end()
        self.device.queue.submit([encoder.finish()])
        runs = int(np.frombuffer(self.device.queue.read_buffer(trips), np.uint32)[1])
        trips.destroy()
        return LLVMPIPE_LOOP_ITERATION_LIMIT if runs < wanted else None

    def require(self, limit: str, needed: int, what: str, *, largest: str = "") -> None:
        """DeviceLimitError unless `needed` is within `limit`; `largest` says what the limit allows
        in the caller's terms ("22,369,621 records"), added to the message."""
        available = self.device.limits[limit]
        if needed > available:
            allows = f" ({largest} at most)" if largest else ""
            raise DeviceLimitError(
                f"{what} needs {limit} = {needed:,} but the adapter {self.adapter_name} offers {available:,}{allows}"
            )


_context: GpuContext | None = None
# Two threads asking first must not create two devices.
_context_lock = threading.Lock()


def _quiet_runtime_dir() -> None:
    # Mesa's Vulkan WSI warns on every process start when XDG_RUNTIME_DIR is unset; a private
    # empty directory is all it asks for.
    if not os.environ.get("XDG_RUNTIME_DIR"):
        os.environ["XDG_RUNTIME_DIR"] = tempfile.mkdtemp(prefix="wgputrace-xdg-")


def new_context() -> GpuContext:
    """A new adapter and device of their own; everything but tests wants `gpu()`'s."""
    _quiet_runtime_dir()
    adapter = wgpu.gpu.request_adapter_sync(power_preference="high-performance")
    if adapter is None:
        raise RuntimeError("wgpu found no adapter; on Debian install mesa-vulkan-drivers for a CPU fallback")
    wanted = {name: adapter.limits[name] for name in LIMITS_WE_USE}
    # subgroup operations: only the lane-counting kernel variant uses them (`KernelVariant.count_lanes`)
    features = [f for f in ("timestamp-query", "subgroup") if f in adapter.features]
    with reporting(f"creating a device on {adapter.info['device']}"):
        device = adapter.request_device_sync(required_limits=wanted, required_features=features)
        fence = device.create_buffer(label="fence", size=_FENCE_BYTES, usage=wgpu.BufferUsage.COPY_SRC)
    return GpuContext(adapter, device, fence)


def gpu() -> GpuContext:
    """The process-wide adapter and device, created on first call, and created again once that
    device is lost (objects made on the lost one stay unusable: make them again from this)."""
    global _context
    with _context_lock:
        if _context is None or _context.lost_reason is not None:
            _context = new_context()
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
