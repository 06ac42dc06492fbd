"""The progressive renderer: scene buffers on the GPU, one path-tracing dispatch per sample per
pixel, a drift-free accumulation buffer, and the mean image read back on request."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..gpu.buffers import read_buffer, storage_buffer, uniform_buffer
from ..gpu.device import DeviceLimitError, GpuContext, gpu
from ..gpu.layout import ACCUMULATED_PIXEL, FRAME
from ..gpu.pipeline import INTEGRATORS, ComputeKernel, compute_kernel, dispatch_size
from ..scene import Scene
from .lights import light_table
from .rng_seed import pixel_rng_states
from .scene_buffers import scene_records

# max_depth = -1 means no limit: paths end by Russian roulette or by leaving the scene.
UNLIMITED_DEPTH = -1
_UNLIMITED_DEPTH_GPU = 0xFFFFFFFF

# Dispatches per submit grow until one submit takes about this long, so progress reports stay
# frequent on slow adapters and submit overhead stays small on fast ones.
_TARGET_SUBMIT_SECONDS = 0.25
_MAX_DISPATCHES_PER_SUBMIT = 64

_kernels: dict[tuple[int, str, str], ComputeKernel] = {}


def path_tracer_kernel(context: GpuContext, acceleration: str, integrator: str) -> ComputeKernel:
    """The megakernel with the traversal for `acceleration` and the `integrator` compiled in
    (cached per process)."""
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {INTEGRATORS}, got {integrator!r}")
    key = (id(context.device), acceleration, integrator)
    if key not in _kernels:
        traversal = f'//! include "traverse_{acceleration}.wgsl"\n'
        _kernels[key] = compute_kernel(
            context,
            "path_tracer.wgsl",
            generated={"acceleration.wgsl": traversal},
            constants={"INTEGRATOR": INTEGRATORS.index(integrator)},
            label=f"path tracer ({acceleration}, {integrator})",
        )
    return _kernels[key]


@dataclass
class RenderStats:
    samples_per_pixel: int = 0
    render_seconds: float = 0.0

    @property
    def samples_per_second(self) -> float:
        return 0.0 if self.render_seconds == 0 else self.samples_per_pixel / self.render_seconds


class Renderer:
    """Keeps the device and the scene's buffers; each `render` call adds samples to the mean."""

    def __init__(
        self,
        scene: Scene,
        width: int = 512,
        height: int = 512,
        *,
        seed: int = 1,
        max_depth: int = 9,
        accel: str = "bvh",
        integrator: str = "mis",
    ) -> None:
        if width < 1 or height < 1:
            raise ValueError(f"image size must be at least 1x1, got {width}x{height}")
        if max_depth != UNLIMITED_DEPTH and max_depth < 1:
            raise ValueError(f"max_depth must be >= 1 (or -1 for no limit), got {max_depth}")
        self.context = gpu()
        self.scene, self.width, self.height, self.seed, self.max_depth = scene, width, height, seed, max_depth
        self.records = scene_records(scene, accel)
        self.accel = accel
        loop_limit = self.context.loop_iteration_limit
        if accel == "flat" and loop_limit is not None and self.triangle_count > loop_limit:
            # the flat list tests every triangle of every box a ray enters, in one loop
            raise DeviceLimitError(
                f"--accel flat tests up to {self.triangle_count:,} triangles per ray, but {self.context.adapter_name} "
                f"ends shader loops after {loop_limit:,} iterations; use the BVH"
            )
        self.stats = RenderStats()
        pixels = width * height
        groups = dispatch_size(width, height, (8, 8))
        for count in groups[:2]:
            self.context.require("max-compute-workgroups-per-dimension", count, f"a {width}x{height} image")

        device = self.context.device
        self.integrator = integrator
        self.kernel = path_tracer_kernel(self.context, accel, integrator)
        self.lights = light_table(self.records.triangles, self.records.materials)
        self._frame = uniform_buffer(self.context, "frame", self._frame_record())
        self._rng = storage_buffer(self.context, "rng states", pixel_rng_states(seed, pixels))
        self._accumulation = storage_buffer(
            self.context, "accumulation", ACCUMULATED_PIXEL.zeros(pixels), read_back=True
        )
        scene_buffers = {
            1: storage_buffer(self.context, "triangles", self.records.triangles),
            2: storage_buffer(self.context, "bvh nodes", self.records.nodes),
            3: storage_buffer(self.context, "materials", self.records.materials),
            6: storage_buffer(self.context, "lights", self.lights.entries),
        }
        self._bind_group = self.kernel.bind_group(
            self.context, 0, {0: self._frame, **scene_buffers, 4: self._rng, 5: self._accumulation}
        )
        self._groups = groups
        self._dispatches_per_submit = 1
        self._device = device

    @property
    def triangle_count(self) -> int:
        return len(self.records.triangles)

    @property
    def samples_per_pixel(self) -> int:
        return self.stats.samples_per_pixel

    def _frame_record(self) -> np.ndarray:
        right, up, forward = self.scene.camera.image_plane(self.width, self.height)
        record = FRAME.zeros(1)
        record["camera_position"] = self.scene.camera.position
        record["camera_right"], record["camera_up"], record["camera_forward"] = right, up, forward
        record["width"], record["height"] = self.width, self.height
        record["max_depth"] = _UNLIMITED_DEPTH_GPU if self.max_depth == UNLIMITED_DEPTH else self.max_depth
        record["node_count"] = len(self.records.nodes)
        record["light_count"] = self.lights.count
        record["light_weight_total"] = self.lights.total_weight
        return record

    def _submit(self, dispatches: int) -> None:
        encoder = self._device.create_command_encoder()
        for _ in range(dispatches):
            compute = encoder.begin_compute_pass()
            compute.set_pipeline(self.kernel.pipeline)
            compute.set_bind_group(0, self._bind_group)
            compute.dispatch_workgroups(*self._groups)
            compute.end()
        self._device.queue.submit([encoder.finish()])
        self.context.finish()

    def render(self, spp: int, progress: Callable[[int], None] | None = None) -> RenderStats:
        """Add `spp` samples per pixel; `progress(n)` is called after every n samples finish."""
        if spp < 0:
            raise ValueError(f"spp must be >= 0, got {spp}")
        done = 0
        while done < spp:
            batch = min(self._dispatches_per_submit, spp - done)
            start = time.perf_counter()
            self._submit(batch)
            seconds = time.perf_counter() - start
            done += batch
            self.stats.samples_per_pixel += batch
            self.stats.render_seconds += seconds
            if progress is not None:
                progress(batch)
            if seconds < _TARGET_SUBMIT_SECONDS / 2:
                self._dispatches_per_submit = min(2 * self._dispatches_per_submit, _MAX_DISPATCHES_PER_SUBMIT)
        return self.stats

    def _accumulated(self) -> np.ndarray:
        return read_buffer(self.context, self._accumulation, ACCUMULATED_PIXEL.dtype, self.width * self.height)

    def image(self) -> np.ndarray:
        """The mean of all samples so far: float32 (height, width, 3), linear radiance, row 0 on top."""
        pixels = self._accumulated()
        total = pixels["sum"][:, :3].astype(np.float64) - pixels["compensation"][:, :3]
        mean = total / max(self.stats.samples_per_pixel, 1)
        return mean.astype(np.float32).reshape(self.height, self.width, 3)

    @property
    def nonfinite_samples(self) -> int:
        """How many samples were NaN or infinite (each was dropped and counted as zero)."""
        return int(self._accumulated()["sum"][:, 3].astype(np.float64).sum())

    def reset(self) -> None:
        """Forget all samples (the random sequence continues, so new samples are independent)."""
        self._device.queue.write_buffer(self._accumulation, 0, ACCUMULATED_PIXEL.zeros(self.width * self.height))
        self.stats = RenderStats()


def render(
    scene: Scene,
    spp: int = 64,
    width: int = 512,
    height: int = 512,
    *,
    seed: int = 1,
    max_depth: int = 9,
    accel: str = "bvh",
    integrator: str = "mis",
) -> np.ndarray:
    """Render `scene` from scratch: the mean of `spp` samples per pixel, float32 (H, W, 3)."""
    renderer = Renderer(scene, width, height, seed=seed, max_depth=max_depth, accel=accel, integrator=integrator)
    renderer.render(spp)
    return renderer.image()


__all__ = ["Renderer", "RenderStats", "UNLIMITED_DEPTH", "render"]
