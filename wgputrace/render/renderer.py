"""The progressive renderer: scene buffers on the GPU, one path-tracing dispatch per sample per
pixel, a drift-free accumulation buffer, and the mean image read back on request.

Edits to the scene reach the GPU at the next `render` (or `update`): only the records that changed
are uploaded (SceneMirror finds them, TrackedBuffer merges them into write_buffer calls), and
accumulation restarts only when some uploaded byte changed. A restart also puts every pixel's
random sequence back at the seed, on the GPU, so the picture after an edit is the picture a fresh
Renderer of the edited scene makes with the same seed."""

from __future__ import annotations

import signal
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import wgpu

from ..denoise import denoise
from ..gpu.alpha import GENERATED_ALPHA, alpha_hook
from ..gpu.bdpt import BDPT_MAX_DEPTH, GENERATED_BDPT, bdpt_hook
from ..gpu.bindings import (
    BAND_GROUP,
    RAY_COUNT_GROUP,
    BindGroup,
    lights_group,
    pixels_group,
    scene_group,
    shading_group,
)
from ..gpu.buffers import PARAMETER_BINDING_LIMIT, PARAMETER_USAGE, read_buffer, storage_buffer, write_buffer
from ..gpu.device import DeviceLimitError, GpuContext, gpu
from ..gpu.emission import GENERATED_EMISSION, emission_hook
from ..gpu.generated import (
    BVH_STACK_SIZE,
    GENERATED_TRAVERSAL_STACK,
    INTEGRATORS,
    PATH_TRACER_INTEGRATORS,
    traversal_stack,
    traversal_stack_size,
)
from ..gpu.kernel import ComputeKernel
from ..gpu.layout import ACCUMULATED_PIXEL, FRAME
from ..gpu.light_dispatch import (
    GENERATED_ESCAPED_LIGHT,
    GENERATED_LIGHT_EMISSION,
    GENERATED_LIGHTS,
    NO_LIGHTS,
    LightFeatures,
    escaped_light_hook,
    light_dispatch,
    light_emission_dispatch,
)
from ..gpu.material_dispatch import ALL_KINDS, GENERATED_MATERIALS, material_dispatch, shaded_kinds
from ..gpu.path_guides import GENERATED_PATH_GUIDES, path_guides_hook
from ..gpu.ray_count import GENERATED_RAY_COUNT, ray_count_hook
from ..gpu.sampler import DEFAULT_SAMPLER, GENERATED_SAMPLER, check_sampler, sampler_hook
from ..gpu.shading_normals import GENERATED_SHADING_NORMALS, shading_normals_hook
from ..gpu.texels import TrackedTexels
from ..gpu.textures import GENERATED_TEXTURES, textures_hook
from ..gpu.tracked_buffer import TrackedBuffer, UploadCount
from ..scene import Camera, Scene
from .interrupts import Deferral, deferred_signals
from .light_buffers import LightBuffers
from .lights import LightTable
from .limits import atlas_side, check_image_size, check_scene_size, fit_environment
from .rng_seed import pixel_rng_states
from .scene_buffers import SceneRecords
from .scene_sync import CORNER_ATTRIBUTES, LIGHTS, MATERIALS, NODES, TEXTURE_ATLAS, TRIANGLES, SceneMirror
from .sobol import pixel_sobol_states
from .splats import refused_splats, splat_sums, zeroed_splats
from .texture_buffers import TextureBuffers

# max_depth = -1 means no limit: paths end by Russian roulette or by leaving the scene.
UNLIMITED_DEPTH = -1
_UNLIMITED_DEPTH_GPU = 0xFFFFFFFF

# Dispatches per submit grow until one submit takes about this long, so progress reports stay
# frequent on slow adapters and submit overhead stays small on fast ones.
_TARGET_SUBMIT_SECONDS = 0.25
_MAX_DISPATCHES_PER_SUBMIT = 64


class SubmitPlan:
    """How many dispatches (samples per pixel) the next submit holds: the count doubles while a
    submit takes under half of _TARGET_SUBMIT_SECONDS (up to _MAX_DISPATCHES_PER_SUBMIT), never
    exceeds the samples left, and under a time budget never exceeds what the last measured time
    per dispatch fits in the time remaining, so the last submit ends near the deadline instead of
    up to _TARGET_SUBMIT_SECONDS after it."""

    def __init__(self) -> None:
        self.dispatches = 1
        self.seconds_per_dispatch: float | None = None

    def next(self, left: int | None = None, remaining_seconds: float | None = None) -> int:
        """Dispatches for the next submit (0: none fits); `left`: samples still wanted (None: no
        cap), `remaining_seconds`: time left in the budget (None: no budget)."""
        count = self.dispatches if left is None else min(self.dispatches, left)
        if remaining_seconds is not None and self.seconds_per_dispatch is not None:
            count = min(count, max(int(remaining_seconds / self.seconds_per_dispatch), 0))
        return count

    def measured(self, dispatches: int, seconds: float) -> None:
        """A submit of `dispatches` took `seconds`, waiting included."""
        self.seconds_per_dispatch = seconds / dispatches
        if seconds < _TARGET_SUBMIT_SECONDS / 2:
            self.dispatches = min(2 * self.dispatches, _MAX_DISPATCHES_PER_SUBMIT)


@dataclass(frozen=True)
class SceneVariant:
    """What a scene compiles into every kernel that traces it: the traversal (and its stack), the
    lights besides emissive triangles, smooth shading, textures, see-through surfaces and emissive
    textures (path_tracer_kernel's options of the same names). The path tracer and the viewer's
    guides take their generated hooks and extra bind groups from here, so both see one scene."""

    acceleration: str
    stack_size: int = BVH_STACK_SIZE
    lights: LightFeatures = NO_LIGHTS
    smooth: bool = False
    textured: bool = False
    see_through: bool = False
    emissive_surfaces: bool = False

    def groups(self) -> tuple[BindGroup, ...]:
        """The bind groups besides the scene's: the lights group and the shading group where used."""
        lights = (lights_group(self.lights),) if self.lights.any else ()
        shading = (shading_group(self.smooth, self.textured),) if self.smooth or self.textured else ()
        return lights + shading

    def generated(self) -> dict[str, str]:
        """The generated files of this variant, by name."""
        return {
            "generated/acceleration.wgsl": f'//! include "geometry/traverse_{self.acceleration}.wgsl"\n',
            GENERATED_TRAVERSAL_STACK: traversal_stack(self.stack_size),
            GENERATED_LIGHTS: light_dispatch(self.lights),
            GENERATED_ESCAPED_LIGHT: escaped_light_hook(self.lights),
            GENERATED_SHADING_NORMALS: shading_normals_hook(self.smooth, self.textured),
            GENERATED_TEXTURES: textures_hook(self.textured),
            GENERATED_ALPHA: alpha_hook(self.see_through),
            GENERATED_EMISSION: emission_hook(self.emissive_surfaces),
        }


_kernels: dict[tuple, ComputeKernel] = {}


def path_tracer_kernel(
    context: GpuContext,
    acceleration: str,
    integrator: str,
    overrides: dict[str, float] | None = None,
    *,
    rows: bool = False,
    material_kinds: frozenset[int] = ALL_KINDS,
    count_rays: bool = False,
    guides: bool = False,
    stack_size: int = BVH_STACK_SIZE,
    lights: LightFeatures = NO_LIGHTS,
    smooth: bool = False,
    textured: bool = False,
    see_through: bool = False,
    emissive_surfaces: bool = False,
    sampler: str = DEFAULT_SAMPLER,
) -> ComputeKernel:
    """The megakernel with the traversal for `acceleration` and the `integrator` compiled in
    (cached per process). `overrides` sets other WGSL override constants of integrators/path_tracer.wgsl
    (for measurements such as bench/glossy_light_sampling.py). `rows` compiles the entry point
    that renders a band of rows (integrators/path_tracer_rows.wgsl, for the viewer). `material_kinds` limits
    the BSDF code compiled in to those kinds (gpu/material_dispatch.py). `count_rays` compiles the
    ray counters in (gpu/ray_count.py; render/ray_count.py runs them). `guides` compiles in the
    denoiser's albedo and normal guides (gpu/path_guides.py) and binds their sums in the pixels
    group. `stack_size` sizes the BVH traversal's stack (gpu/generated.py traversal_stack_size).
    `lights` compiles in the code of the lights besides emissive triangles (gpu/light_dispatch.py)
    and declares the lights group they are bound in; none by default. `smooth` compiles in shading
    with per-vertex normals (gpu/shading_normals.py) and declares the shading group; `textured`
    compiles in the materials' textures (gpu/textures.py) and declares their bindings in that group;
    `see_through` (textured scenes only) compiles into every ray's triangle test the alpha modes and
    single-sided surfaces (gpu/alpha.py), which slow that test; `emissive_surfaces` (textured scenes
    only) the light that materials emit through their texture records (gpu/emission.py). `sampler`
    chooses what stands behind sample_1d and sample_2d (gpu/sampler.py). The "bdpt" integrator is
    its own kernel (shaders/integrators/bdpt.wgsl), which also binds the splat sums in the pixels group and has
    no band-of-rows entry point."""
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {INTEGRATORS}, got {integrator!r}")
    bidirectional = integrator == "bdpt"
    if bidirectional and rows:
        raise ValueError("the bdpt integrator renders whole images only: it has no band-of-rows kernel for the viewer")
    check_sampler(sampler)
    overrides = overrides or {}
    kinds = shaded_kinds(material_kinds)
    key = (
        id(context.device),
        acceleration,
        integrator,
        tuple(sorted(overrides.items())),
        rows,
        kinds,
        count_rays,
        guides,
        stack_size,
        lights,
        smooth,
        textured,
        see_through,
        emissive_surfaces,
        sampler,
    )
    if key not in _kernels:
        variant = SceneVariant(acceleration, stack_size, lights, smooth, textured, see_through, emissive_surfaces)
        groups = (scene_group(acceleration), pixels_group(guides, bidirectional), *((BAND_GROUP,) if rows else ()))
        groups += ((RAY_COUNT_GROUP,) if count_rays else ()) + variant.groups()
        generated = {
            **variant.generated(),
            GENERATED_MATERIALS: material_dispatch(kinds),
            GENERATED_RAY_COUNT: ray_count_hook(count_rays),
            GENERATED_PATH_GUIDES: path_guides_hook(guides, kinds),
            GENERATED_SAMPLER: sampler_hook(sampler),
        }
        if bidirectional:
            generated |= {GENERATED_LIGHT_EMISSION: light_emission_dispatch(lights), GENERATED_BDPT: bdpt_hook(lights)}
            entry, constants = "integrators/bdpt.wgsl", dict(overrides)
        else:
            entry = "integrators/path_tracer_rows.wgsl" if rows else "integrators/path_tracer.wgsl"
            constants = {"INTEGRATOR": PATH_TRACER_INTEGRATORS.index(integrator), **overrides}
        _kernels[key] = ComputeKernel(
            context,
            entry,
            groups,
            generated=generated,
            constants=constants,
            label=f"path tracer ({acceleration}, {integrator}{', rows' if rows else ''}"
            f"{', counting rays' if count_rays else ''}{', guides' if guides else ''}"
            f"{', ' + lights.description if lights.any else ''}{', smooth shading' if smooth else ''}{', textured' if textured else ''}{', see-through' if see_through else ''}"
            f"{', emissive surfaces' if emissive_surfaces else ''}, {sampler} sampler)",
            entry_point="main_rows" if rows else "main",
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
    """Keeps the device and the scene's buffers; each `render` call adds samples to the mean.

    With `guides` (or `guides_enabled` set later), every sample also adds the albedo and shading
    normal the denoiser takes as guides (`guides()`); without, the path tracer compiles no guide
    code and the renderer allocates no guide buffer. `sampler` (gpu/sampler.py SAMPLERS) chooses
    where the paths' random numbers come from: independent streams or Owen-scrambled Sobol points,
    each pixel's sequence taken in order across `render` calls either way."""

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
    ) -> None:
        check_sampler(sampler)
        if width < 1 or height < 1:
            raise ValueError(f"image size must be at least 1x1, got {width}x{height}")
        if max_depth != UNLIMITED_DEPTH and not 1 <= max_depth < _UNLIMITED_DEPTH_GPU:
            raise ValueError(
                f"max_depth must be from 1 to {_UNLIMITED_DEPTH_GPU - 1:,} (or -1 for no limit), got {max_depth}"
            )
        if integrator == "bdpt" and not 1 <= max_depth <= BDPT_MAX_DEPTH:
            raise ValueError(f"integrator 'bdpt' takes max_depth from 1 to {BDPT_MAX_DEPTH}, got {max_depth}")
        self.context = gpu()
        self.scene, self.width, self.height, self.seed, self.max_depth = scene, width, height, seed, max_depth
        # before anything is allocated and before the BVH build, which takes seconds for millions of triangles
        check_image_size(self.context, width, height, guides, splats=integrator == "bdpt")
        fit_environment(self.context, scene)
        check_scene_size(self.context, scene, accel)
        self._mirror = SceneMirror(scene, accel, atlas_side(self.context))
        self.accel = accel
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
        pixels = width * height
        device = self.context.device
        self.integrator = integrator
        self.sampler = sampler
        self._shader_overrides = shader_overrides
        self._kinds = shaded_kinds(self._mirror.material_kinds)
        self._stack_size = self._needed_stack_size()
        self._lights = LightBuffers(self.context, self._mirror)
        self._light_features = self._mirror.light_features
        self._guides = guides
        # the corner attributes (shading normals), only for a scene with per-vertex normals
        self._corner_attributes = self._new_corner_attributes()
        # the textures' bindings, only for a scene whose materials read textures
        self._textures = TextureBuffers(self.context, self._mirror)
        self._textured = self._mirror.textured
        self._see_through = self._mirror.see_through
        self._emissive_surfaces = self._mirror.emissive_surfaces
        self.kernel = self.kernel_variant()
        frame = self._frame_record()
        self._frame_bytes = frame.tobytes()
        self._frame = TrackedBuffer(
            self.context,
            "frame",
            PARAMETER_USAGE,
            frame,
            binding_limit=PARAMETER_BINDING_LIMIT,
            spare=False,
        )
        states = self._sampler_states(replicate=0)
        # resets since the last restart: each gives the Sobol sampler an independent scramble
        self._replicate = 0
        self._rng = storage_buffer(self.context, "rng states", states)
        # the states at the seed, copied over the live ones on the GPU when accumulation restarts
        self._rng_at_seed = storage_buffer(self.context, "rng states at the seed", states, read_back=True)
        self._accumulation = storage_buffer(
            self.context, "accumulation", ACCUMULATED_PIXEL.zeros(pixels), read_back=True
        )
        self._guide_sums = self._new_guide_sums() if guides else None
        # light tracing's splats, only for the bidirectional path tracer
        self._splats = (
            storage_buffer(self.context, "splats", zeroed_splats(pixels), read_back=True)
            if integrator == "bdpt"
            else None
        )
        # COPY_SRC: what was uploaded can be read back and checked against the host records
        storage = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC
        limit = "max-storage-buffer-binding-size"
        self._scene_buffers = {
            # triangles and the BVH's nodes as texels (gpu/texels.py: faster loads on lavapipe); the
            # flat list's boxes in a buffer, as geometry/traverse_flat.wgsl reads them
            TRIANGLES: TrackedTexels(self.context, "triangles", self._mirror.triangles),
            NODES: TrackedTexels(self.context, "bvh nodes", self._mirror.nodes)
            if accel == "bvh"
            else TrackedBuffer(self.context, "bvh nodes", storage, self._mirror.nodes, binding_limit=limit),
            MATERIALS: TrackedBuffer(self.context, "materials", storage, self._mirror.materials, binding_limit=limit),
            LIGHTS: TrackedBuffer(self.context, "lights", storage, self._mirror.lights.entries, binding_limit=limit),
        }
        self._submits = SubmitPlan()
        self._device = device
        self._bind()

    @property
    def records(self) -> SceneRecords:
        """The scene's GPU records as last uploaded (triangles in BVH order, nodes, materials, BVH)."""
        return self._mirror.records

    @property
    def lights(self) -> LightTable:
        return self._mirror.lights

    @property
    def triangle_count(self) -> int:
        return len(self._mirror.triangles)

    @property
    def smooth_shading(self) -> bool:
        """Whether the scene has per-vertex normals, which the path tracer then shades with."""
        return self._corner_attributes is not None

    @property
    def _shading_buffers(self) -> list[TrackedBuffer]:
        corner_attributes = [] if self._corner_attributes is None else [self._corner_attributes]
        return corner_attributes + list(self._textures.buffers.values())

    @property
    def upload_stats(self) -> dict[str, UploadCount]:
        """Bytes and write_buffer calls per buffer made by the last `update` (which every `render`
        starts with); buffers it did not write are absent. Restarting accumulation clears and
        copies buffers on the GPU and uploads nothing."""
        buffers = [self._frame, *self._scene_buffers.values(), *self._lights.buffers.values(), *self._shading_buffers]
        return {buffer.label: buffer.uploads for buffer in buffers if buffer.uploads.calls}

    @property
    def gpu_scene_bytes(self) -> dict[str, int]:
        """Bytes allocated on the GPU for the scene, by buffer (capacity, spare rows included), the
        lights besides emissive triangles, the corner attributes and the textures (the atlas) included."""
        buffers = [*self._scene_buffers.values(), *self._lights.buffers.values(), *self._shading_buffers]
        return {buffer.label: buffer.capacity_bytes for buffer in buffers}

    @property
    def gpu_image_bytes(self) -> dict[str, int]:
        """Bytes allocated on the GPU for the image, by buffer: they grow with the pixels, not the
        scene (the frame uniform is a fixed 80 bytes)."""
        buffers = (self._frame.buffer, self._rng, self._rng_at_seed, self._accumulation, self._guide_sums, self._splats)
        return {buffer.label: buffer.size for buffer in buffers if buffer is not None}

    @property
    def gpu_texture_bytes(self) -> int:
        """Bytes of the texture atlas on the GPU (0 without textures): texture memory, which grows
        with the images rather than the triangles, so it is reported beside the bytes per triangle."""
        atlas = self._textures.buffers.get(TEXTURE_ATLAS)
        return 0 if atlas is None else atlas.capacity_bytes

    @property
    def gpu_bytes_per_triangle(self) -> float:
        """Scene bytes on the GPU (triangles, BVH nodes, materials, lights, per-corner attributes;
        not the texture atlas: gpu_texture_bytes) per triangle."""
        return (sum(self.gpu_scene_bytes.values()) - self.gpu_texture_bytes) / self.triangle_count

    def update(self) -> dict[str, UploadCount]:
        """Bring the GPU up to date with the scene: upload only the records that changed, refit or
        rebuild the BVH, switch to the pipeline for the scene's material kinds, and restart
        accumulation if anything the GPU reads changed. Returns `upload_stats`."""
        for buffer in (self._frame, *self._scene_buffers.values(), *self._shading_buffers):
            buffer.uploads = UploadCount()
        texture_generation = self._textures.generation
        generations = [buffer.generation for buffer in self._scene_buffers.values()]
        fit_environment(self.context, self.scene)
        changes = self._mirror.update()
        arrays = {
            TRIANGLES: self._mirror.triangles,
            NODES: self._mirror.nodes,
            MATERIALS: self._mirror.materials,
            LIGHTS: self._mirror.lights.entries,
        }
        for name, rows in changes.items():
            if name in self._scene_buffers:
                self._scene_buffers[name].upload(arrays[name], rows)
        light_generation = self._lights.generation
        self._lights.sync(self._mirror, changes)
        shading_before = self._shading_state()
        self._sync_corner_attributes(changes)
        self._textures.sync(self._mirror, changes)
        frame = self._frame_record()
        frame_changed = frame.tobytes() != self._frame_bytes
        if frame_changed:
            self._frame.upload(frame)
            self._frame_bytes = frame.tobytes()
        kinds, stack_size = shaded_kinds(self._mirror.material_kinds), self._needed_stack_size()
        features = self._mirror.light_features
        smoothness_changed = (shading_before is not None) != self.smooth_shading
        texturing_changed = self._textured != self._mirror.textured
        self._textured = self._mirror.textured
        see_through_changed = self._see_through != self._mirror.see_through
        self._see_through = self._mirror.see_through
        emission_changed = self._emissive_surfaces != self._mirror.emissive_surfaces
        self._emissive_surfaces = self._mirror.emissive_surfaces
        new_pipeline = (
            smoothness_changed
            or texturing_changed
            or see_through_changed
            or emission_changed
            or (kinds, stack_size, features)
            != (
                self._kinds,
                self._stack_size,
                self._light_features,
            )
        )
        if new_pipeline:
            self._kinds, self._stack_size, self._light_features = kinds, stack_size, features
            self.kernel = self.kernel_variant()
        rebind = generations != [buffer.generation for buffer in self._scene_buffers.values()]
        rebind = rebind or shading_before != self._shading_state() or texture_generation != self._textures.generation
        if new_pipeline or rebind or light_generation != self._lights.generation:
            self._bind()
        if changes or frame_changed or smoothness_changed or texturing_changed:
            self.restart()
        return self.upload_stats

    def _bind(self) -> None:
        """Bind groups of the scene (made again when an edit reallocates one of its buffers) and of the pixels."""
        scene = {name: buffer.resource for name, buffer in self._scene_buffers.items()}
        self._bind_groups = {
            "scene": self.kernel.bind("scene", frame=self._frame.buffer, **scene),
            "pixels": self.kernel.bind("pixels", **self._pixel_resources()),
        }
        if self._light_features.any:
            self._bind_groups["lights"] = self.kernel.bind("lights", **self._lights.resources)
        if self._corner_attributes is not None or self._textured:
            self._bind_groups["shading"] = self.kernel.bind("shading", **self._shading_resources())

    def _shading_resources(self) -> dict[str, object]:
        """What the shading group binds: the corner attributes where the scene is smooth, the
        textures where it is textured."""
        smooth = {} if self._corner_attributes is None else {"corner_attributes": self._corner_attributes.buffer}
        return {**smooth, **self._textures.resources}

    def _new_corner_attributes(self) -> TrackedBuffer | None:
        """The corner attributes' buffer, for a scene with per-vertex normals (else None)."""
        records = self._mirror.corner_attributes
        if records is None:
            return None
        usage = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC
        return TrackedBuffer(
            self.context, "corner attributes", usage, records, binding_limit="max-storage-buffer-binding-size"
        )

    def _shading_state(self) -> tuple[int, int] | None:
        """Which corner attributes' buffer is bound (None: flat shading): a change means rebinding."""
        buffer = self._corner_attributes
        return None if buffer is None else (id(buffer), buffer.generation)

    def _sync_corner_attributes(self, changes: dict[str, np.ndarray]) -> None:
        """Upload the corner attributes' changed rows; make or free their buffer where the scene
        gained or lost its per-vertex normals."""
        records = self._mirror.corner_attributes
        if records is None or self._corner_attributes is None:
            if self._corner_attributes is not None:
                self._corner_attributes.buffer.destroy()
            self._corner_attributes = self._new_corner_attributes()
        elif CORNER_ATTRIBUTES in changes:
            self._corner_attributes.upload(records, changes[CORNER_ATTRIBUTES])

    def _pixel_resources(self) -> dict[str, wgpu.GPUBuffer]:
        """What the pixels group binds: the guide sums too where guides are on."""
        resources = {"rng_states": self._rng, "accumulation": self._accumulation}
        if self._guide_sums is not None:
            resources["guide_sums"] = self._guide_sums
        if self._splats is not None:
            resources["splats"] = self._splats
        return resources

    def _new_guide_sums(self) -> wgpu.GPUBuffer:
        """Zeroed guide sums: two Kahan sums per pixel, the albedo's and the normal's (gpu/bindings.py pixels_group)."""
        return storage_buffer(
            self.context, "guide sums", ACCUMULATED_PIXEL.zeros(2 * self.width * self.height), read_back=True
        )

    @property
    def guides_enabled(self) -> bool:
        """Whether every sample also accumulates the denoiser's guides (`guides()`)."""
        return self._guides

    @guides_enabled.setter
    def guides_enabled(self, enabled: bool) -> None:
        """Switch the guides on or off: compiles or chooses the kernel variant, allocates or frees
        the guide sums, and restarts accumulation (the samples so far have no guides to match)."""
        enabled = bool(enabled)
        if enabled == self._guides:
            return
        if enabled:
            check_image_size(self.context, self.width, self.height, guides=True, splats=self._splats is not None)
            self._guide_sums = self._new_guide_sums()
        else:
            self._guide_sums.destroy()
            self._guide_sums = None
        self._guides = enabled
        self.kernel = self.kernel_variant()
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
        encoder = self._device.create_command_encoder()
        encoder.clear_buffer(self._accumulation)
        if self._guide_sums is not None:
            encoder.clear_buffer(self._guide_sums)
        if self._splats is not None:
            encoder.clear_buffer(self._splats)
        encoder.copy_buffer_to_buffer(self._rng_at_seed, 0, self._rng, 0, self._rng.size)
        self.context.submit(encoder, "restarting accumulation")
        self._replicate = 0
        self.stats = RenderStats()

    def _sampler_states(self, replicate: int) -> np.ndarray:
        """Every pixel's sampler state at the seed: a xoshiro128** state, or a Sobol seed for
        `replicate` (render/sobol.py) and no samples taken."""
        pixels = self.width * self.height
        if self.sampler == "sobol":
            return pixel_sobol_states(self.seed, pixels, replicate)
        return pixel_rng_states(self.seed, pixels)

    def kernel_variant(self, **options) -> ComputeKernel:
        """This renderer's path tracer (acceleration, integrator, overrides, material kinds, stack
        size, lights, guides on or off) compiled with other `path_tracer_kernel` options, e.g. count_rays=True."""
        return path_tracer_kernel(
            self.context,
            self.accel,
            self.integrator,
            self._shader_overrides,
            material_kinds=self._kinds,
            stack_size=self._stack_size,
            lights=self._light_features,
            smooth=self.smooth_shading,
            textured=self._textured,
            see_through=self._see_through,
            emissive_surfaces=self._emissive_surfaces,
            sampler=self.sampler,
            **{"guides": self._guides, **options},
        )

    @property
    def scene_variant(self) -> SceneVariant:
        """What this renderer's scene compiles into the kernels that trace it, as it is now."""
        return SceneVariant(
            self.accel,
            self._stack_size,
            self._light_features,
            self.smooth_shading,
            self._textured,
            self._see_through,
            self._emissive_surfaces,
        )

    @property
    def traversal_stack_size(self) -> int:
        """Entries of the BVH traversal stack compiled into this renderer's path tracer."""
        return self._stack_size

    def _needed_stack_size(self) -> int:
        """The stack the scene's tree needs (bvh/wide.py counts it), rounded up to STACK_SIZE_STEP."""
        wide = self._mirror.wide
        return traversal_stack_size(wide.max_stack) if wide is not None else BVH_STACK_SIZE

    @property
    def samples_per_pixel(self) -> int:
        return self.stats.samples_per_pixel

    @property
    def bind_groups(self) -> dict[str, wgpu.GPUBindGroup]:
        """The path tracer's bind groups by name ("scene", "pixels", and "lights" where the scene has
        lights besides emissive triangles; gpu/bindings.py), current after the last `update`: other
        kernels declaring these groups set them as they are."""
        return dict(self._bind_groups)

    @property
    def resources(self) -> dict[str, object]:
        """What the bind groups hold, by binding name (the frame uniform, the scene's buffers and
        texel views, rng_states, accumulation, and guide_sums where guides are on), for kernels that
        read them elsewhere (the viewer's)."""
        scene = {name: buffer.resource for name, buffer in self._scene_buffers.items()}
        shading = self._shading_resources()
        return {"frame": self._frame.buffer, **scene, **self._pixel_resources(), **self._lights.resources, **shading}

    def set_camera(self, camera: Camera) -> None:
        """Look through `camera` from now on: uploads only the frame uniform, restarts accumulation."""
        self.scene.camera = camera
        self.update()

    def _frame_record(self) -> np.ndarray:
        right, up, forward = self.scene.camera.image_plane(self.width, self.height)
        record = FRAME.zeros(1)
        record["camera_position"] = self.scene.camera.position
        record["camera_right"], record["camera_up"], record["camera_forward"] = right, up, forward
        record["width"], record["height"] = self.width, self.height
        record["max_depth"] = _UNLIMITED_DEPTH_GPU if self.max_depth == UNLIMITED_DEPTH else self.max_depth
        record["node_count"] = len(self._mirror.nodes)
        record["light_count"] = self.lights.count
        record["light_weight_total"] = self.lights.total_weight
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

    def _submit(self, dispatches: int, deferral: Deferral) -> None:
        """Run `dispatches` samples per pixel in one submit, wait for them and count them; no signal
        can come between the submit and the count."""
        with deferral.shield():
            start = time.perf_counter()
            self.kernel.dispatch((self.width, self.height), self._bind_groups, repeat=dispatches, wait=True)
            seconds = time.perf_counter() - start
            self.stats.samples_per_pixel += dispatches
            self.stats.render_seconds += seconds
        self._submits.measured(dispatches, seconds)

    def _accumulated(self) -> np.ndarray:
        return read_buffer(self.context, self._accumulation, ACCUMULATED_PIXEL.dtype, self.width * self.height)

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
        return denoise(image, **(self.guides() if self._guides else {}))

    def _mean(self, sums: np.ndarray, splats: np.ndarray | float = 0.0) -> np.ndarray:
        """float32 (n, 3): the means of n Kahan sums (ACCUMULATED_PIXEL records) over the samples so
        far, with light tracing's `splats` (float64 (n, 3) sums) added to them first."""
        total = sums["sum"][:, :3].astype(np.float64) - sums["compensation"][:, :3] + splats
        return (total / max(self.stats.samples_per_pixel, 1)).astype(np.float32)

    def _splat_words(self) -> np.ndarray:
        return read_buffer(self.context, self._splats, np.uint32, self._splats.size // 4)

    def _splat_sums(self) -> np.ndarray | float:
        """Light tracing's sums per pixel, float64 (n, 3), or 0 where nothing splats."""
        return 0.0 if self._splats is None else splat_sums(self._splat_words())

    def guides(self) -> dict[str, np.ndarray]:
        """The denoiser's guides, means over the same samples as `image()` (a sample it dropped adds
        zero to them too): "albedo" in [0, 1] and "normal" in [-1, 1], float32 (height, width, 3).
        Each sample gives the albedo and the shading normal (world space, facing the camera's ray)
        of its path's first vertex that is not a mirror or glass (shaders/integrators/denoiser_guides.wgsl); zero
        where it escaped or ended before one. Normals are means, not renormalised: Open Image
        Denoise takes them as they are."""
        if self._guide_sums is None:
            raise ValueError("guides are off: make the Renderer with guides=True or set guides_enabled = True first")
        pixels = self.width * self.height
        sums = read_buffer(self.context, self._guide_sums, ACCUMULATED_PIXEL.dtype, 2 * pixels).reshape(pixels, 2)
        shape = (self.height, self.width, 3)
        # the float32 means of values within the bounds can round past them by an ulp
        albedo = np.clip(self._mean(sums[:, 0]), 0.0, 1.0).reshape(shape)
        normal = np.clip(self._mean(sums[:, 1]), -1.0, 1.0).reshape(shape)
        return {"albedo": albedo, "normal": normal}

    @property
    def nonfinite_samples(self) -> int:
        """How many samples were NaN or infinite (each was dropped and counted as zero); under bdpt
        also light tracing's splats dropped for a non-finite or out-of-range value."""
        refused = 0 if self._splats is None else refused_splats(self._splat_words())
        return self._dropped_sample_counts()[0] + refused

    @property
    def cut_short_samples(self) -> int:
        """How many samples the driver's loop budget may have cut short (llvmpipe's 65,535 loop
        iterations per invocation, shaders/integrators/loop_budget.wgsl); each was dropped and counted as zero."""
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
        write_buffer(self.context, self._accumulation, 0, ACCUMULATED_PIXEL.zeros(self.width * self.height))
        if self._splats is not None:
            write_buffer(self.context, self._splats, 0, zeroed_splats(self.width * self.height))
        if self.sampler == "sobol":
            self._replicate += 1
            write_buffer(self.context, self._rng, 0, self._sampler_states(self._replicate))
        if self._guide_sums is not None:
            write_buffer(self.context, self._guide_sums, 0, ACCUMULATED_PIXEL.zeros(2 * self.width * self.height))
        self.stats = RenderStats()


def render(scene: Scene, spp: int = 64, width: int = 512, height: int = 512, **options) -> np.ndarray:
    """Render `scene` from scratch: the mean of `spp` samples per pixel, float32 (H, W, 3).
    `options` are the Renderer's keyword arguments (seed, max_depth, accel, integrator, sampler, ...)."""
    renderer = Renderer(scene, width, height, **options)
    renderer.render(spp)
    return renderer.image()


__all__ = ["Renderer", "RenderStats", "UNLIMITED_DEPTH", "render"]
