"""The progressive renderer: scene buffers on the GPU, path-tracing dispatches of one or more
samples per pixel, a drift-free accumulation buffer, and the mean image read back on request.

Edits to the scene reach the GPU at the next `render` (or `update`): only the records that changed
are uploaded (SceneMirror finds them, GpuRecords writes their runs), and
accumulation restarts only when some uploaded byte changed. A restart also puts every pixel's
random sequence back at the seed, on the GPU, so the picture after an edit is the picture a fresh
Renderer of the edited scene makes with the same seed."""

from __future__ import annotations

import signal
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import wgpu

from ..denoise import denoise
from ..gpu.buffers import (
    PARAMETER_BINDING_LIMIT,
    PARAMETER_USAGE,
    read_buffer,
    storage_buffer,
    uniform_buffer,
    write_buffer,
)
from ..gpu.device import DeviceLimitError, gpu
from ..gpu.kernel import ComputeKernel, Pass, submit
from ..gpu.layout import ACCUMULATED_PIXEL, FRAME, GBUFFER_PIXEL
from ..gpu.tracked_buffer import TrackedBuffer, UploadCount
from ..integrators import Integrator
from ..integrators import integrator as _integrator
from ..integrators.splats import SPLATS, refused_splats, splat_sums
from ..kernels.bind_groups import GUIDE_SUMS
from ..kernels.compile import tracing_kernel
from ..kernels.sampler import DEFAULT_SAMPLER
from ..kernels.variant import KernelVariant
from ..scene import Camera, Scene
from .gpu_records import GpuRecords
from .interrupts import Deferral, deferred_signals
from .limits import atlas_side, check_image_size, check_scene_size, fit_environment
from .object_motion import ObjectMotion
from .rng_seed import pixel_rng_states
from .scene_mirror import TEXTURE_ATLAS, TRIANGLES, SceneMirror
from .scene_records import SceneRecords
from .sobol import pixel_sobol_states
from .svgf_filter import VarianceGuidedFilter, picture_image
from .temporal_accumulation import TemporalAccumulation
from .temporal_antialiasing import TemporalAntialiasing
from .temporal_upsampling import TemporalUpsampling, check_upscale, frame_gain, subset_offset

# max_depth = -1 means no limit: paths end by Russian roulette or by leaving the scene.
UNLIMITED_DEPTH = -1
_UNLIMITED_DEPTH_GPU = 0xFFFFFFFF

# Samples per submit grow until one submit takes about this long, so progress reports stay
# frequent on slow adapters and submit overhead stays small on fast ones.
_TARGET_SUBMIT_SECONDS = 0.25
_MAX_SAMPLES_PER_SUBMIT = 64


class SubmitPlan:
    """How many samples per pixel the next submit adds: one first (the first progress report comes
    soon, and the time per sample is known before a time budget is spent on more), then at least
    one dispatch's `step`, the count doubling while a submit takes under half of
    _TARGET_SUBMIT_SECONDS (up to _MAX_SAMPLES_PER_SUBMIT, or one dispatch if that takes more). It
    never exceeds the samples left, and under a time budget never exceeds what the last measured
    time per sample fits in the time remaining, so the last submit ends near the deadline instead
    of up to _TARGET_SUBMIT_SECONDS (or a dispatch of `step` samples) after it."""

    def __init__(self, step: int = 1) -> None:
        self.step = step
        self.samples = 1
        self.most = max(step, _MAX_SAMPLES_PER_SUBMIT)
        self.seconds_per_sample: float | None = None

    def next(self, left: int | None = None, remaining_seconds: float | None = None) -> int:
        """Samples for the next submit (0: none fits); `left`: samples still wanted (None: no
        cap), `remaining_seconds`: time left in the budget (None: no budget)."""
        count = self.samples if left is None else min(self.samples, left)
        if remaining_seconds is not None and self.seconds_per_sample is not None:
            count = min(count, max(int(remaining_seconds / self.seconds_per_sample), 0))
        return count

    def measured(self, samples: int, seconds: float) -> None:
        """A submit of `samples` took `seconds`, waiting included."""
        self.seconds_per_sample = seconds / samples
        grown = 2 * self.samples if seconds < _TARGET_SUBMIT_SECONDS / 2 else self.samples
        self.samples = min(max(grown, self.step), self.most)


@dataclass
class RenderStats:
    samples_per_pixel: int = 0
    render_seconds: float = 0.0

    @property
    def samples_per_second(self) -> float:
        return 0.0 if self.render_seconds == 0 else self.samples_per_pixel / self.render_seconds


class Renderer:
    """Keeps the device and the scene's buffers; each `render` call adds samples to the mean.

    Args:
        scene: what to render; edits to it reach the GPU at the next `render` (or `update`).
        width: the image's width in pixels.
        height: the image's height in pixels.
        seed: the random seed: same seed, adapter and arguments, the same image bit for bit.
        max_depth: the most path segments, Mitsuba's meaning; UNLIMITED_DEPTH (-1): no limit.
        accel: "bvh", or "flat" (trac0r's list of boxes, for comparisons).
        integrator: a registered integrator's name (`integrator_names`): "mis", "nee", "bsdf" or
            "bdpt"; each has a page under the plugins reference.
        shader_overrides: WGSL override constants by name, such as MITSUBA_SHADING_NORMALS; each
            set compiles its own pipeline.
        guides: every sample also adds the albedo and shading normal the denoiser takes as guides
            (`guides()`; or set `guides_enabled` later); without, no guide code or buffer.
        sampler: one of SAMPLERS, "sobol" (Owen-scrambled Sobol points) or "independent"; each
            pixel's sequence is taken in order across `render` calls either way.
        samples_per_dispatch: the most samples of a pixel one dispatch takes (path regeneration:
            a path that ends starts the pixel's next one in the same pass); None lets the
            integrator choose for the adapter (more on a CPU adapter, 1 on a GPU). The image is
            the same bit for bit whatever it is.

    Raises:
        ValueError: a size, depth, acceleration, integrator, sampler or override out of range, naming it.
        DeviceLimitError: the image or scene needs more than the adapter (or the host's free memory)
            offers, naming the limit, the value asked and the largest allowed.
        GpuFailure: wgpu refused or lost the work, naming the buffer and its size.
    """

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
        shader_overrides: dict[str, float] | None = None,
        guides: bool = False,
        sampler: str = DEFAULT_SAMPLER,
        samples_per_dispatch: int | None = None,
    ) -> None:
        method = _integrator(integrator).with_overrides(shader_overrides or {})
        if width < 1 or height < 1:
            raise ValueError(f"image size must be at least 1x1, got {width}x{height}")
        if max_depth != UNLIMITED_DEPTH and not 1 <= max_depth < _UNLIMITED_DEPTH_GPU:
            raise ValueError(
                f"max_depth must be from 1 to {_UNLIMITED_DEPTH_GPU - 1:,} (or -1 for no limit), got {max_depth}"
            )
        method.check_depth(max_depth)
        method.check_materials(scene.materials)
        # the variant without its scene: checks the sampler and the overrides before anything is allocated
        variant = KernelVariant(
            integrator=method,
            sampler=sampler,
            guides=guides,
            overrides=tuple((shader_overrides or {}).items()),
            samples_per_dispatch=1 if samples_per_dispatch is None else samples_per_dispatch,
        )
        self.context = gpu()
        if samples_per_dispatch is None:
            chosen = method.samples_per_dispatch(self.context.adapter.info["adapter_type"])
            variant = replace(variant, samples_per_dispatch=chosen)
        # the samples of a regenerating invocation share the driver's loop budget (regeneration_hook)
        shared_budget = variant.samples_per_dispatch > 1 and self.context.loop_iteration_limit is not None
        variant = replace(variant, loop_budget=shared_budget)
        self.scene, self.width, self.height, self.seed, self.max_depth = scene, width, height, seed, max_depth
        # before anything is allocated and before the BVH build, which takes seconds for millions of triangles
        check_image_size(self.context, width, height, guides, method)
        fit_environment(self.context, scene)
        check_scene_size(self.context, scene, accel)
        scene.camera.check_image(width, height)
        self._mirror = SceneMirror(scene, accel, atlas_side(self.context))
        loop_limit = self.context.loop_iteration_limit
        # The flat list tests every triangle for each of a path's rays (a camera or extension ray
        # and a shadow ray per vertex), and the driver's loop budget covers the whole path.
        flat_iterations = 2 * max_depth * self.triangle_count
        if accel == "flat" and loop_limit is not None and flat_iterations > loop_limit:
            raise DeviceLimitError(
                f"--accel flat tests up to {self.triangle_count:,} triangles per ray, {flat_iterations:,} per path of "
                f"max depth {max_depth}, but {self.context.adapter_name} ends shader loops after {loop_limit:,} "
                "iterations per invocation; use the BVH"
            )
        self.stats = RenderStats()
        self.variant = variant.with_scene(self._mirror.features)
        self._compile(self.variant)
        frame = self.frame_record()
        self._frame_bytes = frame.tobytes()
        self._frame = TrackedBuffer(
            self.context, "frame", PARAMETER_USAGE, frame, binding_limit=PARAMETER_BINDING_LIMIT, spare=False
        )
        self._records = GpuRecords(self.context)
        self._records.sync(self._mirror.arrays, {}, self.variant.groups())
        states = self._sampler_states(replicate=0)
        # resets since the last restart: each gives the Sobol sampler an independent scramble
        self._replicate = 0
        self._rng = storage_buffer(self.context, "rng states", states)
        # the states at the seed, copied over the live ones on the GPU when accumulation restarts
        self._rng_at_seed = storage_buffer(self.context, "rng states at the seed", states, read_back=True)
        # what every sample adds to, by binding name, all zeroed when accumulation restarts: the
        # accumulation, the guide sums where guides are on, and the integrator's own arrays
        self._sums = {"accumulation": self._zeroed_sums("accumulation", ACCUMULATED_PIXEL.size)}
        if guides:
            self._sums[GUIDE_SUMS.name] = self._new_guide_sums()
        for array in method.pixel_arrays:
            self._sums[array.binding.name] = self._zeroed_sums(array.binding.name, array.bytes_per_pixel)
        # the samples each invocation takes in the next dispatch, where the kernel takes more than one,
        # and under a loop budget the samples each pixel still owes and their total
        self._dispatch_samples = storage_buffer(self.context, "dispatch samples", np.ones(1, np.uint32))
        self._dispatch_count = 1
        owed = np.zeros(width * height if self.variant.loop_budget else 1, np.uint32)
        self._owed = {
            "owed_samples": storage_buffer(self.context, "owed samples", owed, read_back=True),
            "owed_total": storage_buffer(self.context, "owed total", np.zeros(1, np.uint32), read_back=True),
        }
        self._submits = SubmitPlan(self.samples_per_dispatch)
        # what render_frame keeps from frame to frame, made by its first call
        self._temporal: TemporalAccumulation | None = None
        self._gbuffer: wgpu.GPUBuffer | None = None
        # the integrator's arrays kept from frame to frame (Integrator.frame_arrays), each frame's
        # and the previous one's, by binding name
        self._frame_arrays: dict[str, wgpu.GPUBuffer] = {}
        # whether the last `_sync` found the scene changed, not only the camera
        self._scene_edited = False
        self._previous_frame: wgpu.GPUBuffer | None = None
        self._motion: ObjectMotion | None = None
        self._filter: VarianceGuidedFilter | None = None
        self._upsampling: TemporalUpsampling | None = None
        self._antialiasing: TemporalAntialiasing | None = None
        self._bind()

    @property
    def integrator(self) -> Integrator:
        return self.variant.integrator

    @property
    def accel(self) -> str:
        return self.variant.scene.acceleration

    @property
    def sampler(self) -> str:
        return self.variant.sampler

    @property
    def samples_per_dispatch(self) -> int:
        """The most samples of each pixel one dispatch takes (the last of a render may take fewer)."""
        return self.variant.samples_per_dispatch

    @property
    def records(self) -> SceneRecords:
        """The scene's GPU records as last uploaded (triangles in BVH order, nodes, materials, BVH)."""
        return self._mirror.records

    @property
    def triangle_count(self) -> int:
        """Triangles stored on the GPU: an instanced mesh's once, however many instances draw it."""
        return len(self._mirror.arrays[TRIANGLES])

    @property
    def smooth_shading(self) -> bool:
        """Whether the scene has per-vertex normals, which the kernel then shades with."""
        return self.variant.scene.smooth

    @property
    def upload_stats(self) -> dict[str, UploadCount]:
        """Bytes and write_buffer calls per buffer made by the last `update` (which every `render`
        starts with); buffers it did not write are absent. Restarting accumulation clears and
        copies buffers on the GPU and uploads nothing."""
        frame = {self._frame.label: self._frame.uploads} if self._frame.uploads.calls else {}
        return frame | self._records.uploads

    @property
    def gpu_scene_bytes(self) -> dict[str, int]:
        """Bytes allocated on the GPU for the scene, by buffer (capacity, spare rows included): every
        record array the kernel binds, the lights' and the textures' (the atlas) included."""
        return self._records.capacity_bytes

    @property
    def gpu_image_bytes(self) -> dict[str, int]:
        """Bytes allocated on the GPU for the image, by buffer: they grow with the pixels, not the
        scene (the frame uniforms are a fixed 80 bytes); render_frame's G-buffer and histories too
        once it has run."""
        buffers = (self._frame.buffer, self._rng, self._rng_at_seed, *self._sums.values())
        if self._temporal is not None:
            buffers += (self._gbuffer, self._previous_frame, *self._temporal.buffers, *self._frame_arrays.values())
        if self._upsampling is not None:
            buffers += self._upsampling.buffers
        if self._filter is not None:
            buffers += self._filter.buffers
        if self._antialiasing is not None:
            buffers += self._antialiasing.buffers
        return {buffer.label: buffer.size for buffer in buffers}

    @property
    def gpu_texture_bytes(self) -> int:
        """Bytes of the texture atlas on the GPU (0 without textures): texture memory, which grows
        with the images rather than the triangles, so it is reported beside the bytes per triangle."""
        return self.gpu_scene_bytes.get(TEXTURE_ATLAS, 0)

    @property
    def gpu_bytes_per_triangle(self) -> float:
        """Scene bytes on the GPU (triangles, BVH nodes, materials, lights, per-vertex attributes;
        not the texture atlas: gpu_texture_bytes) per triangle."""
        return (sum(self.gpu_scene_bytes.values()) - self.gpu_texture_bytes) / self.triangle_count

    def update(self) -> dict[str, UploadCount]:
        """Bring the GPU up to date with the scene: upload only the records that changed, refit or
        rebuild the BVH, switch to the kernel variant for the scene's features, and restart
        accumulation if anything the GPU reads changed. Returns `upload_stats`."""
        if self._sync():
            self.restart()
        return self.upload_stats

    def _sync(self) -> bool:
        """`update` without the restart: whether anything the GPU reads changed."""
        self._frame.uploads = UploadCount()
        self.variant.require_integrator().check_materials(self.scene.materials)
        fit_environment(self.context, self.scene)
        changes = self._mirror.update()
        variant = self.variant.with_scene(self._mirror.features)
        regrouped = self._records.sync(*self._record_arrays(changes), variant.groups())
        frame = self.frame_record()
        frame_changed = frame.tobytes() != self._frame_bytes
        if frame_changed:
            self._frame.upload(frame)
            self._frame_bytes = frame.tobytes()
        new_variant = variant != self.variant
        if new_variant:
            if variant.scene.camera != self.variant.scene.camera:
                self.scene.camera.check_image(self.width, self.height)
            self.variant = variant
            self._compile(variant)
        if new_variant or regrouped:
            self._bind()
        self._scene_edited = bool(changes or new_variant)
        # a new variant with no record changed still changes the picture: normals or textures dropped
        return bool(changes or frame_changed or new_variant)

    def _record_arrays(self, changes: dict[str, np.ndarray]) -> tuple[dict, dict]:
        """The record arrays GpuRecords keeps and their changed rows: the mirror's (`changes`), and
        the objects' motions once render_frame has begun."""
        if self._motion is None:
            return self._mirror.arrays, changes
        moved = self._motion.update(self.scene, self._mirror)
        return self._mirror.arrays | self._motion.arrays, changes | moved

    def _bind(self) -> None:
        """Every bind group of the kernel: made again when the variant changes or an edit
        reallocates one of a group's resources."""
        self._bind_groups = {
            group.name: self.kernel.bind(group.name, **self._bound_in(group.name)) for group in self.variant.groups()
        }

    def _bound_in(self, group: str) -> dict[str, object]:
        """What the renderer binds in `group`, by binding name."""
        if group == "pixels":
            frames = {"gbuffer": self._gbuffer, "previous_frame": self._previous_frame} if self.variant.gbuffer else {}
            frames |= self._frame_arrays if self.variant.gbuffer else {}
            return {"rng_states": self._rng, **self._sums, **frames, **self._records.bound_in(group)}
        if group == "dispatch":
            return {"dispatch_samples": self._dispatch_samples, **(self._owed if self.variant.loop_budget else {})}
        extra = {"frame": self._frame.buffer} if group == "scene" else {}
        return extra | self._records.bound_in(group)

    def _zeroed_sums(self, label: str, bytes_per_pixel: int) -> wgpu.GPUBuffer:
        return storage_buffer(
            self.context, label, np.zeros(self.width * self.height * bytes_per_pixel, np.uint8), read_back=True
        )

    def _new_guide_sums(self) -> wgpu.GPUBuffer:
        """Zeroed guide sums: two Kahan sums per pixel, the albedo's and the normal's (GUIDE_SUMS)."""
        return self._zeroed_sums("guide sums", 2 * ACCUMULATED_PIXEL.size)

    @property
    def guides_enabled(self) -> bool:
        """Whether every sample also accumulates the denoiser's guides (`guides()`)."""
        return self.variant.guides

    @guides_enabled.setter
    def guides_enabled(self, enabled: bool) -> None:
        """Switch the guides on or off: compiles or chooses the kernel variant, allocates or frees
        the guide sums, and restarts accumulation (the samples so far have no guides to match)."""
        enabled = bool(enabled)
        if enabled == self.variant.guides:
            return
        if enabled:
            check_image_size(self.context, self.width, self.height, True, self.integrator)
            self._sums[GUIDE_SUMS.name] = self._new_guide_sums()
        else:
            self._sums.pop(GUIDE_SUMS.name).destroy()
        self.variant = replace(self.variant, guides=enabled)
        self._compile(self.variant)
        self._bind()
        self.restart()

    def restart(self, seed: int | None = None) -> None:
        """Forget all samples and put every pixel's random sequence back at the seed, on the GPU: the
        samples that follow repeat the first ones bit for bit. With `seed`, the renderer continues as
        a fresh Renderer of that seed would start (a cluster worker's next batch), its pipeline and
        buffers kept."""
        if seed is not None and seed != self.seed:
            self.seed = seed
            write_buffer(self.context, self._rng_at_seed, 0, self._sampler_states(replicate=0))
        encoder = self.context.device.create_command_encoder()
        for buffer in self._sums.values():
            encoder.clear_buffer(buffer)
        encoder.copy_buffer_to_buffer(self._rng_at_seed, 0, self._rng, 0, self._rng.size)
        self.context.submit(encoder, "restarting accumulation")
        self._replicate = 0
        self.stats = RenderStats()
        self._restart_frames()

    def _sampler_states(self, replicate: int) -> np.ndarray:
        """Every pixel's sampler state at the seed: a xoshiro128** state, or a Sobol seed for
        `replicate` (`pixel_sobol_states`) and no samples taken."""
        pixels = self.width * self.height
        if self.sampler == "sobol":
            return pixel_sobol_states(self.seed, pixels, replicate)
        return pixel_rng_states(self.seed, pixels)

    @property
    def samples_per_pixel(self) -> int:
        return self.stats.samples_per_pixel

    @property
    def bind_groups(self) -> dict[str, wgpu.GPUBindGroup]:
        """The kernel's bind groups by name ("scene", "pixels", and "lights" and "shading" where the
        scene uses them), current after the last `update`: other kernels declaring these groups
        set them as they are."""
        return dict(self._bind_groups)

    @property
    def resources(self) -> dict[str, object]:
        """What the bind groups hold, by binding name (the frame, the scene's records, rng_states,
        accumulation, guide_sums where guides are on...), for kernels that read them elsewhere."""
        return {name: resource for group in self._bind_groups for name, resource in self._bound_in(group).items()}

    def set_camera(self, camera: Camera) -> None:
        """Look through `camera` from now on: uploads only the frame uniform, restarts accumulation."""
        self.scene.camera = camera
        self.update()

    def frame_record(self, width: int | None = None, height: int | None = None) -> np.ndarray:
        """The FRAME record of the scene's camera for an image of `width` x `height` (this
        renderer's by default; the viewer traces smaller ones while moving)."""
        width, height = width or self.width, height or self.height
        record = FRAME.zeros(1)
        self.scene.camera.fill_frame(record, width, height)
        record["width"], record["height"] = width, height
        record["max_depth"] = _UNLIMITED_DEPTH_GPU if self.max_depth == UNLIMITED_DEPTH else self.max_depth
        record["node_count"] = len(self._mirror.nodes)
        lights = self._mirror.lights
        record["light_count"], record["light_weight_total"] = lights.count, lights.total_weight
        return record

    def render(
        self,
        spp: int | None = None,
        progress: Callable[[int], None] | None = None,
        *,
        seconds: float | None = None,
        stop: Callable[[], bool] | None = None,
    ) -> RenderStats:
        """Add `spp` samples per pixel; or, with `seconds`, as many as fit in that time (at least
        one; `spp` then caps them); `stop()`, asked before every submit, ends the render early when
        true. `progress(n)` is called after every n samples finish.

        In the main thread a SIGINT (Ctrl-C) is answered after the submit in flight finished and
        was counted, by raising `Interrupted` (a KeyboardInterrupt): `image()` is then the mean of
        the complete samples and `samples_per_pixel` says how many. A second SIGINT raises
        `Aborted` (a KeyboardInterrupt too) at once, which leaves the renderer as consistent."""
        if spp is None and seconds is None and stop is None:
            raise ValueError("render needs spp, seconds or stop to know when to end")
        if spp is not None and spp < 0:
            raise ValueError(f"spp must be >= 0, got {spp}")
        if seconds is not None and not seconds > 0:
            raise ValueError(f"seconds must be > 0, got {seconds}")
        deadline = None if seconds is None else time.perf_counter() + seconds
        with deferred_signals(signal.SIGINT) as deferral:
            self.update()
            done = 0
            while True:
                deferral.check()
                if (spp is not None and done >= spp) or (stop is not None and stop()):
                    break
                remaining = None if deadline is None else deadline - time.perf_counter()
                batch = self._submits.next(None if spp is None else spp - done, remaining)
                if batch == 0 and done == 0:
                    batch = 1  # a time budget gets at least one sample per pixel
                if batch == 0:
                    break
                self._submit(batch, deferral)
                done += batch
                if progress is not None:
                    progress(batch)
        return self.stats

    def _submit(self, samples: int, deferral: Deferral) -> None:
        """Add `samples` samples per pixel, wait for them and count them; no signal can come between
        the submit and the count."""
        with deferral.shield():
            start = time.perf_counter()
            self.dispatch(samples)
            seconds = time.perf_counter() - start
            self.stats.samples_per_pixel += samples
            self.stats.render_seconds += seconds
        self._submits.measured(samples, seconds)

    def dispatch_sizes(self, samples: int) -> list[int]:
        """The samples per pixel of each dispatch that adds `samples`: samples_per_dispatch each,
        the last fewer."""
        full, rest = divmod(samples, self.samples_per_dispatch)
        return [self.samples_per_dispatch] * full + ([rest] if rest else [])

    def dispatch(
        self,
        samples: int,
        kernel: ComputeKernel | None = None,
        extra_groups: dict[str, wgpu.GPUBindGroup] | None = None,
    ) -> None:
        """Add `samples` samples per pixel (`dispatch_sizes`) and wait for them, without counting
        them in `stats`; under a loop budget it returns once no pixel owes a sample. `kernel`:
        another variant of the renderer's kernel (a counting one) that also binds `extra_groups`."""
        kernel = kernel or self.kernel
        groups = {**self._bind_groups, **(extra_groups or {})}
        sizes = self.dispatch_sizes(samples)
        # one submit per run of dispatches that take the same count, written before it
        for count in dict.fromkeys(sizes):
            self._submit_dispatches(kernel, groups, count, sizes.count(count))
        self.context.finish()
        # Under a loop budget, samples left to later dispatches (regeneration_hook) are taken by
        # dispatches of no samples, each taking one from every pixel that owes some.
        while self.variant.loop_budget and read_buffer(self.context, self._owed["owed_total"], np.uint32, 1)[0]:
            write_buffer(self.context, self._owed["owed_total"], 0, np.zeros(1, np.uint32))
            self._submit_dispatches(kernel, groups, 0, 1)
            self.context.finish()

    def _submit_dispatches(self, kernel: ComputeKernel, groups: dict, count: int, repeat: int) -> None:
        """One submit of `repeat` dispatches of `count` samples each (after the samples owed), each
        after the integrator's pre-pass where it has one."""
        if count != self._dispatch_count:
            write_buffer(self.context, self._dispatch_samples, 0, np.array([count], np.uint32))
            self._dispatch_count = count
        size = (self.width, self.height)
        prepass = [Pass(self._prepass, size, groups)] if self._prepass is not None else []
        submit(self.context, [*prepass, Pass(kernel, size, groups)] * repeat)

    def _compile(self, variant: KernelVariant) -> None:
        """`variant`'s kernel, and its integrator's pre-pass where it has one."""
        self.kernel = tracing_kernel(self.context, variant)
        uses_prepass = variant.require_integrator().uses_prepass(variant)
        self._prepass = tracing_kernel(self.context, replace(variant, prepass=True)) if uses_prepass else None

    def _accumulated(self) -> np.ndarray:
        return read_buffer(self.context, self._sums["accumulation"], ACCUMULATED_PIXEL.dtype, self.width * self.height)

    def image(self, denoised: bool = False) -> np.ndarray:
        """The mean of all samples so far: float32 (height, width, 3), linear radiance, row 0 on top.

        `denoised`: that mean denoised by Intel Open Image Denoise (`wgputrace.denoise`), guided by
        `guides()` where guides are on, else from the colour alone (guides help most at edges and
        behind glass: make the Renderer with guides=True). Needs the `denoise` extra (raises
        DenoiserMissing without it). Dropped samples never reach the denoiser (the mean counts them
        as zero), and denoise refuses any non-finite or negative pixel with a ValueError naming it."""
        image = self._mean(self._accumulated(), self._splat_sums()).reshape(self.height, self.width, 3)
        if not denoised:
            return image
        return denoise(image, **(self.guides() if self.guides_enabled else {}))

    def _mean(self, sums: np.ndarray, splats: np.ndarray | float = 0.0) -> np.ndarray:
        """float32 (n, 3): the means of n Kahan sums (ACCUMULATED_PIXEL records) over the samples so
        far, with light tracing's `splats` (float64 (n, 3) sums) added to them first."""
        total = sums["sum"][:, :3].astype(np.float64) - sums["compensation"][:, :3] + splats
        return (total / max(self.stats.samples_per_pixel, 1)).astype(np.float32)

    def _splat_words(self) -> np.ndarray:
        splats = self._sums[SPLATS.binding.name]
        return read_buffer(self.context, splats, np.uint32, splats.size // 4)

    def _splat_sums(self) -> np.ndarray | float:
        """Light tracing's sums per pixel, float64 (n, 3), or 0 where the integrator does not splat."""
        return splat_sums(self._splat_words()) if self.integrator.splats else 0.0

    def guides(self) -> dict[str, np.ndarray]:
        """The denoiser's guides, means over the same samples as `image()` (a sample it dropped adds
        zero to them too): "albedo" in [0, 1] and "normal" in [-1, 1], float32 (height, width, 3).
        Each sample gives the albedo and the shading normal (world space, facing the camera's ray) of
        its path's first vertex that is not a mirror or glass (`guide_vertex`); zero where it escaped
        or ended before one. Normals are means, not renormalised: Open Image Denoise takes them as is.
        """
        if not self.guides_enabled:
            raise ValueError("guides are off: make the Renderer with guides=True or set guides_enabled = True first")
        pixels = self.width * self.height
        guide_sums = self._sums[GUIDE_SUMS.name]
        sums = read_buffer(self.context, guide_sums, ACCUMULATED_PIXEL.dtype, 2 * pixels).reshape(pixels, 2)
        shape = (self.height, self.width, 3)
        # the float32 means of values within the bounds can round past them by an ulp
        albedo = np.clip(self._mean(sums[:, 0]), 0.0, 1.0).reshape(shape)
        normal = np.clip(self._mean(sums[:, 1]), -1.0, 1.0).reshape(shape)
        return {"albedo": albedo, "normal": normal}

    @property
    def nonfinite_samples(self) -> int:
        """How many samples were NaN or infinite (each was dropped and counted as zero); under bdpt
        also light tracing's splats dropped for a non-finite or out-of-range value."""
        refused = refused_splats(self._splat_words()) if self.integrator.splats else 0
        return self._dropped_sample_counts()[0] + refused

    @property
    def cut_short_samples(self) -> int:
        """How many samples the driver's loop budget may have cut short (llvmpipe's 65,535 loop
        iterations per invocation, `loop_budget_spent`); each was dropped and counted as zero.
        """
        return self._dropped_sample_counts()[1]

    @property
    def dropped_samples(self) -> int:
        """Samples that added nothing to the image: non-finite or cut short."""
        return sum(self._dropped_sample_counts())

    def _dropped_sample_counts(self) -> tuple[int, int]:
        """(non-finite, cut short): the counts accumulate_sample and drop_cut_short_sample keep in
        each pixel's sum.w and compensation.w, from one read-back."""
        pixels = self._accumulated()
        return tuple(int(pixels[field][:, 3].astype(np.float64).sum()) for field in ("sum", "compensation"))

    def reset(self) -> None:
        """Forget all samples; the samples that follow are independent of those before: the
        independent sampler's streams continue, the Sobol sampler starts every pixel's sequence
        again under a new scramble (continuing it would stratify the new samples against the old)."""
        for buffer in self._sums.values():
            write_buffer(self.context, buffer, 0, np.zeros(buffer.size, np.uint8))
        if self.sampler == "sobol":
            self._replicate += 1
            write_buffer(self.context, self._rng, 0, self._sampler_states(self._replicate))
        self.stats = RenderStats()
        self._restart_frames()

    def _restart_frames(self) -> None:
        """Start the histories of render_frame again at the next frame."""
        if self._temporal is not None:
            self._temporal.restart()
        if self._upsampling is not None:
            self._upsampling.restart()

    def render_frame(
        self,
        camera: Camera | None = None,
        spp: int | None = None,
        *,
        budget: float | None = None,
        filtered: bool = False,
        upscale: int = 1,
    ) -> np.ndarray:
        """One frame of a moving picture: look through `camera` (None: the scene's camera as it
        is, after any edits to the scene), trace `spp` samples per pixel (default 1) and add them
        to every pixel's history (TemporalAccumulation). Returns the history's mean: float32
        (height, width, 3), linear radiance, row 0 on top.

        `budget`: seconds for the frame's tracing instead of a sample count: passes are traced
        until it is spent, at least one sample per pixel (`spp` then caps them), as
        `render(seconds=...)` counts them; `stats.samples_per_pixel` says how many were taken
        (with `upscale`, per traced pixel).

        While the camera and the scene stay as they were, a frame adds its samples as `render`
        does: N frames at rest are bit for bit the mean of a fresh Renderer's `render(N * spp)`
        (with one sample per frame). When something changed, each pixel takes the previous
        history where its first hit was seen before (motion vectors), rejects what was hidden
        then, and keeps at most MOVING_HISTORY_FRAMES frames of it. `restart` and `reset` start
        every history again. The first call compiles the G-buffer variant of the kernel (the
        path tracers have one: ValueError for the others) and allocates the history.

        `filtered`: the history's picture through SVGF's variance-guided filter instead
        (VarianceGuidedFilter); in a frame where something moved, the filter's first pass also
        becomes the history the next frame takes, as in SVGF; at rest the history stays unfiltered.

        `upscale`: 2, 4 or 8 traces `spp` samples of one pixel in each upscale x upscale block
        and rebuilds every pixel from its history (TemporalUpsampling); at rest, after N * upscale**2
        frames the picture is bit for bit `render(N * spp)`'s. Changing it starts the history again.
        With `filtered`, the filter reads the upsampled picture and what each pixel's history shows,
        and feeds its first pass back into the moving history as at full resolution; while moving,
        its picture is then blended with the last frame's output (TemporalAntialiasing)."""
        if spp is not None and spp < 1:
            raise ValueError(f"spp must be >= 1, got {spp}")
        if budget is not None and not budget > 0:
            raise ValueError(f"budget must be > 0 seconds, got {budget}")
        if upscale != 1:
            check_upscale(upscale, self.width, self.height)
        if self._temporal is None:
            self._start_frames()
        if camera is not None:
            self.scene.camera = camera
        moving = self._sync()
        # this frame's own samples, the pixels' sequences going on from the last frame's
        encoder = self.context.device.create_command_encoder()
        for buffer in self._sums.values():
            encoder.clear_buffer(buffer)
        history = self._temporal if upscale == 1 and self._upsampling is None else None
        carried = moving and not self._scene_edited and history is not None and not history.fresh
        self._hand_over_frame_arrays(encoder, carried)
        self.context.submit(encoder, "starting a frame")
        self.stats = RenderStats()
        spp = self._add_frame(spp, budget, upscale, moving)
        self._forget_previous_frame_arrays()
        self._motion.frame_done(self.scene)
        write_buffer(self.context, self._previous_frame, 0, np.frombuffer(self._frame_bytes, np.uint8))
        frames = self._temporal if upscale == 1 else self._upsampling
        if not filtered:
            return frames.image()
        if self._filter is None:
            self._filter = VarianceGuidedFilter(self.context, self.width, self.height)
        # SVGF's feedback only into a history that moved: a resting one (and a new one, even if the
        # camera was just set) stays the plain mean
        carried = frames.carried if frames.reprojected else None
        if upscale == 1:
            picture = self._filter.filter(self._temporal.history, self._gbuffer, spp, feedback=carried)
        else:
            # what each pixel's history shows stands for the G-buffer the traced pixels alone have
            surfaces = self._upsampling.surfaces
            gain = frame_gain(upscale, spp)
            picture = self._filter.filter(self._upsampling.shown, surfaces, gain, feedback=carried, upscale=upscale)
            if self._antialiasing is None:
                self._antialiasing = TemporalAntialiasing(self.context, self.width, self.height)
            picture = self._antialiasing.resolve(picture, surfaces, frames.reprojected)
        return picture_image(self.context, picture, self.width, self.height)

    def _hand_over_frame_arrays(self, encoder: wgpu.GPUCommandEncoder, carried: bool) -> None:
        """Clear the integrator's frame arrays (Integrator.frame_arrays) for a frame, the last
        frame's first copied to where the kernel reads them if `carried`: handed over only to a
        frame where the camera alone moved, over the whole image, continuing a history (at rest
        frames stand alone; after an edit, what was learnt may show a light that is gone)."""
        for array in self.variant.require_integrator().frame_arrays:
            written, previous = (self._frame_arrays[name] for name in (array.binding.name, array.previous.name))
            if carried:
                encoder.copy_buffer_to_buffer(written, 0, previous, 0, written.size)
            else:
                encoder.clear_buffer(previous)
            encoder.clear_buffer(written)

    def _forget_previous_frame_arrays(self) -> None:
        """Clear what a frame read of the frame before, so that `render` reads none."""
        arrays = self.variant.require_integrator().frame_arrays
        if arrays:
            encoder = self.context.device.create_command_encoder()
            for array in arrays:
                encoder.clear_buffer(self._frame_arrays[array.previous.name])
            self.context.submit(encoder, "ending a frame")

    def _add_frame(self, spp: int | None, budget: float | None, upscale: int, moving: bool) -> int:
        """Trace a frame of `spp` samples per pixel or `budget` seconds (render_frame) and add it to
        its history: every pixel's (TemporalAccumulation), or one pixel's per block
        (TemporalUpsampling); the history of another kind or factor starts again. Returns the
        samples each traced pixel took, also counted in `stats`."""
        if upscale == 1:
            if self._upsampling is not None:
                self._upsampling = None
                self._temporal.restart()
            self.render(1 if spp is None and budget is None else spp, seconds=budget)
            spp = self.stats.samples_per_pixel
            self._temporal.add_frame(self._sums["accumulation"], self._gbuffer, spp, moving)
            return spp
        if self._upsampling is None or self._upsampling.factor != upscale:
            self._upsampling = TemporalUpsampling(self.context, self.width, self.height, upscale)
        start = time.perf_counter()
        if budget is None:
            self._upsampling.trace(self, 1 if spp is None else spp)
            self.stats.samples_per_pixel = 1 if spp is None else spp
        else:
            # one sample at a time while the last one's time still fits what is left
            taken, last = 0, 0.0
            while taken == 0 or ((spp is None or taken < spp) and time.perf_counter() - start + last <= budget):
                traced = time.perf_counter()
                self._upsampling.trace(self, 1)
                taken, last = taken + 1, time.perf_counter() - traced
            self.stats.samples_per_pixel = taken
        self.stats.render_seconds = time.perf_counter() - start
        self._upsampling.add_frame(self._sums["accumulation"], self._gbuffer, self.stats.samples_per_pixel, moving)
        return self.stats.samples_per_pixel

    def _start_frames(self) -> None:
        """What render_frame needs: the G-buffer variant, the G-buffer, the previous frame's camera
        (this one's, as the first frame has no history to move), the objects' motions and the history."""
        variant = replace(self.variant, gbuffer=True)
        pixels = self.width * self.height
        self._gbuffer = storage_buffer(self.context, "G-buffer", GBUFFER_PIXEL.zeros(pixels), read_back=True)
        self._previous_frame = uniform_buffer(
            self.context, "previous frame", np.frombuffer(self._frame_bytes, np.uint8).copy()
        )
        self.variant = variant
        for array in variant.require_integrator().frame_arrays:
            for binding in (array.binding, array.previous):
                self._frame_arrays[binding.name] = self._zeroed_sums(binding.name, array.bytes_per_pixel)
        self._compile(variant)
        self._motion = ObjectMotion()
        self._records.sync(*self._record_arrays({}), variant.groups())
        self._bind()
        self._temporal = TemporalAccumulation(self.context, self.width, self.height)

    def history_length(self) -> np.ndarray:
        """The samples each pixel's history holds after the last render_frame (the upsampled
        history's after an upscaled frame): float32 (height, width)."""
        if self._temporal is None:
            raise ValueError("no frame has been rendered yet: call render_frame first")
        frames = self._temporal if self._upsampling is None else self._upsampling
        return frames.records()["length"].reshape(self.height, self.width)

    def traced_subset(self) -> tuple[int, tuple[int, int]]:
        """(factor, (x, y)): the last render_frame traced pixel (x, y) of every factor x factor
        block, the others hold no sample of it (`image()`) nor a G-buffer entry; (1, (0, 0)) where
        it traced every pixel."""
        if self._temporal is None:
            raise ValueError("no frame has been rendered yet: call render_frame first")
        upsampling = self._upsampling
        if upsampling is None:
            return 1, (0, 0)
        return upsampling.factor, subset_offset(upsampling.frame - 1, upsampling.factor)

    def gbuffer(self) -> dict[str, np.ndarray]:
        """The last frame's G-buffer (render_frame), what the ray through each pixel's centre first
        hit: "depth" (the camera ray's distance to it; 0 where nothing was hit), "normal" (shading,
        facing the camera), "albedo" (in [0, 1]), "surface" (material index + 1; 0: nothing hit),
        "object" (the shape's index in scene.shapes, or their count + the instance's index in
        scene.instances; 0: nothing hit), "motion" (from this frame's raster position to where the previous camera
        saw the point, moved back with its object, in pixels, x right and y down), "previous_depth"
        and "previous_seen" (the previous camera's distance to the point, 0 where it did not have it
        in front, and whether it did); arrays of (height, width) or (height, width, n). After an
        upscaled frame only the pixels it traced hold that frame's entries."""
        if self._gbuffer is None:
            raise ValueError("no frame has been rendered yet: call render_frame first")
        records = read_buffer(self.context, self._gbuffer, GBUFFER_PIXEL.dtype, self.width * self.height)
        fields = ("depth", "normal", "albedo", "surface", "object", "motion", "previous_depth")
        gbuffer = {name: records[name].reshape(self.height, self.width, *records[name].shape[1:]) for name in fields}
        return gbuffer | {"previous_seen": gbuffer["previous_depth"] > 0.0}


def render(scene: Scene, spp: int = 64, width: int = 512, height: int = 512, **options) -> np.ndarray:
    """Render `scene` from scratch: the mean of `spp` samples per pixel.

    Args:
        scene: what to render, through its camera.
        spp: samples per pixel.
        width: the image's width in pixels.
        height: the image's height in pixels.
        **options: the Renderer's keyword arguments (seed, max_depth, accel, integrator, sampler, ...).

    Returns:
        float32 (height, width, 3), linear radiance, row 0 on top.

    Raises:
        ValueError: a size, depth, integrator, sampler or spp out of range, naming it.
        DeviceLimitError: the image or scene needs more than the adapter offers, naming the limit.
        GpuFailure: wgpu refused or lost the work.
    """
    renderer = Renderer(scene, width, height, **options)
    renderer.render(spp)
    return renderer.image()


__all__ = ["Renderer", "RenderStats", "UNLIMITED_DEPTH", "render"]
