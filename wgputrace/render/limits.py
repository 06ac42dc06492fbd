"""Whether an image and a scene fit the adapter and the host, checked before anything is allocated.

A request too large fails at once with one line naming the limit, the value asked for and the
largest allowed, rather than minutes later in numpy ("Unable to allocate 74.5 GiB") or in wgpu.
Every size is derived from the records the renderer allocates (their GpuStructs, the per-pixel
random states), never written down as a byte count, and the checks are arithmetic only, so sizes
just below and above each limit are cheap to try: an image's (`image_needs`: the dispatch, every
per-pixel buffer, host memory) and a scene's before its BVH is built (`check_scene_counts`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..gpu.bindings import IMAGE_WORKGROUP
from ..gpu.device import DeviceLimitError, GpuContext
from ..gpu.float_texture import require_float_texture
from ..gpu.layout import (
    ACCUMULATED_PIXEL,
    BVH_NODE,
    LIGHT,
    LIGHT_SOURCE,
    MATERIAL,
    TRIANGLE,
    TRIANGLE_VERTICES,
    VERTEX_COLOR,
    VERTEX_NORMAL,
    WIDE_BVH_NODE,
)
from ..gpu.texels import require_texels
from ..gpu.tracked_buffer import require_records
from ..integrators import Integrator
from ..integrators.splats import SPLATS
from ..kernels.bind_groups import LIGHTS_GROUP_INDEX, SHADING_GROUP_INDEX
from ..scene import Scene
from .lights import emitting_kinds
from .rng_seed import pixel_rng_states

# The name the host's memory goes by where a device limit's name would stand.
HOST_MEMORY = "available host memory (bytes)"
RNG_STATE_BYTES = pixel_rng_states(0, 1)[0].nbytes
# The renderer's buffers of one record per pixel, by label: bytes per pixel.
PIXEL_BUFFERS = {
    "rng states": RNG_STATE_BYTES,
    "rng states at the seed": RNG_STATE_BYTES,
    "accumulation": ACCUMULATED_PIXEL.size,
}
# The buffer a renderer with the denoiser's guides adds: the albedo's and the normal's Kahan sums.
GUIDE_BUFFERS = {"guide sums": 2 * ACCUMULATED_PIXEL.size}
PIXEL_BUFFER_LIMITS = ("max-buffer-size", "max-storage-buffer-binding-size")
# pixel_rng_states holds this many times its result at its peak: uint64 pixel indices and both
# uint64 halves of every state, their stack and its copy (56 B per 16-byte state, measured with
# tracemalloc; `test_seeding_peak_is_within_the_model` keeps it true).
SEEDING_PEAK_STATES = 3.5
_RGB = 3
_FLOAT64_RGB_BYTES = _RGB * np.dtype(np.float64).itemsize
_FLOAT32_RGB_BYTES = _RGB * np.dtype(np.float32).itemsize


@dataclass(frozen=True)
class Need:
    """`value` of `limit` (a device limit's name, or HOST_MEMORY) that `what` asks for."""

    limit: str
    value: int
    what: str


def available_host_memory() -> int | None:
    """Bytes the host can give without swapping (MemAvailable of /proc/meminfo); None where the
    file or the field is missing (not Linux, or an old kernel), and host memory goes unchecked."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        return None
    return None


def pixel_buffers(guides: bool = False, integrator: Integrator | None = None) -> dict[str, int]:
    """The renderer's buffers of one record per pixel, by label: bytes per pixel; the guide sums too
    with `guides`, and the `integrator`'s own arrays."""
    arrays = {} if integrator is None else {a.binding.name: a.bytes_per_pixel for a in integrator.pixel_arrays}
    return {**PIXEL_BUFFERS, **(GUIDE_BUFFERS if guides else {}), **arrays}


def host_steps(pixels: int, guides: bool = False, integrator: Integrator | None = None) -> dict[str, int]:
    """Host memory each step of making a Renderer of `pixels` pixels and of one `image()` (with
    `guides`: then one `guides()`; under an `integrator` that splats, image() reads its splat sums
    back too) holds at once, at most. wgpu stages every upload and read-back in a host-visible
    buffer of its size, and keeps that memory after a read-back: lavapipe's VmHWM at 2048x2048 is 188
    B per pixel, as `host_bytes` has it without guides (`test_image_read_back_peak_is_within_the_model`
    covers the numpy part).
    """
    rng = pixels * RNG_STATE_BYTES
    accumulation = pixels * ACCUMULATED_PIXEL.size
    steps = {
        "seeding": int(SEEDING_PEAK_STATES * rng),
        # the states are still held while the zeroed accumulation goes up through its staging copy
        "uploading": rng + 2 * accumulation,
        # wgpu's staging buffer, its bytearray copy, read_buffer's array
        "reading back": 3 * accumulation,
        # the staging memory wgpu kept, read_buffer's array, the float64 sum and mean, the float32 image
        "averaging": 2 * accumulation + pixels * (2 * _FLOAT64_RGB_BYTES + _FLOAT32_RGB_BYTES),
    }
    if integrator is not None and integrator.splats:
        splat_words = pixels * SPLATS.bytes_per_pixel
        # image() holds the accumulation's staging memory and array while the splats come back
        # (staging, its bytearray copy, read_buffer's array) and turn into float64 words, summed
        # per channel through three float64 temporaries (`splat_sums`)
        steps["reading back the splats"] = 2 * accumulation + 5 * splat_words + 3 * pixels * _FLOAT64_RGB_BYTES
        steps["averaging"] += pixels * _FLOAT64_RGB_BYTES
    if guides:
        guide_sums = pixels * GUIDE_BUFFERS["guide sums"]
        image_kept = accumulation + pixels * _FLOAT32_RGB_BYTES  # the image's staging memory, and the image
        steps |= {
            # as the accumulation's upload, after it
            "uploading the guides": rng + 2 * guide_sums,
            "reading back the guides": image_kept + 3 * guide_sums,
            # the staging memory kept and read_buffer's array; the albedo done while the normal is
            # averaged as the image was (its float64 sum and mean, and its float32 mean)
            "averaging the guides": image_kept
            + 2 * guide_sums
            + pixels * (2 * _FLOAT64_RGB_BYTES + 2 * _FLOAT32_RGB_BYTES),
        }
    return steps


def host_bytes(context: GpuContext, pixels: int, guides: bool = False, integrator: Integrator | None = None) -> int:
    """Host memory a Renderer of `pixels` pixels and one `image()` (with `guides`, and one
    `guides()`; with the `integrator`'s arrays) need: their largest step, plus the
    per-pixel buffers themselves where the adapter allocates from host memory. Not the denoiser's
    own memory (Intel Open Image Denoise sizes its work to the memory it finds)."""
    resident = pixels * sum(pixel_buffers(guides, integrator).values()) if context.shares_host_memory else 0
    return resident + max(host_steps(pixels, guides, integrator).values())


def image_needs(
    context: GpuContext, width: int, height: int, guides: bool = False, integrator: Integrator | None = None
) -> list[Need]:
    """What a `width` x `height` image (with the denoiser's guides or not, under `integrator`)
    asks of each limit, in the order they are checked."""
    pixels = width * height
    workgroups = [-(-size // group) for size, group in zip((width, height), IMAGE_WORKGROUP, strict=True)]
    needs = [
        Need("max-compute-workgroups-per-dimension", count, f"the path tracer's dispatch ({axis})")
        for count, axis in zip(workgroups, ("workgroups across", "workgroups down"), strict=True)
    ]
    needs += [
        Need(limit, pixels * record_bytes, f"buffer {label!r}")
        for label, record_bytes in pixel_buffers(guides, integrator).items()
        for limit in PIXEL_BUFFER_LIMITS
    ]
    read_backs = "one image() and one guides() read-back" if guides else "one image() read-back"
    needs.append(Need(HOST_MEMORY, host_bytes(context, pixels, guides, integrator), f"the renderer with {read_backs}"))
    return needs


def _first_excess(context: GpuContext, needs: list[Need], host_memory: int | None) -> tuple[Need, int] | None:
    """The first need over its limit and that limit's value; host memory is skipped when unknown."""
    for need in needs:
        allowed = host_memory if need.limit == HOST_MEMORY else context.device.limits[need.limit]
        if allowed is not None and need.value > allowed:
            return need, allowed
    return None


def _largest_square(context: GpuContext, host_memory: int | None, guides: bool, integrator: Integrator | None) -> int:
    """The side of the largest square image within every limit (0 if none is): a bisection, as
    every need grows with the side."""
    fits, too_big = 0, min(IMAGE_WORKGROUP) * context.device.limits["max-compute-workgroups-per-dimension"] + 1
    while too_big - fits > 1:
        side = (fits + too_big) // 2
        if _first_excess(context, image_needs(context, side, side, guides, integrator), host_memory) is None:
            fits = side
        else:
            too_big = side
    return fits


def largest_square_image(context: GpuContext, guides: bool = False, integrator: Integrator | None = None) -> int:
    """The side of the largest square image this adapter (and this host's free memory) can render,
    with the denoiser's guides or without, under `integrator` (None: one without arrays of its own)."""
    return _largest_square(context, available_host_memory(), guides, integrator)


def check_image_size(
    context: GpuContext, width: int, height: int, guides: bool = False, integrator: Integrator | None = None
) -> None:
    """DeviceLimitError, before anything is allocated, if a `width` x `height` image (with the
    denoiser's guide sums where `guides`, the `integrator`'s pixel arrays)
    exceeds a device limit or the host's available memory: names the limit, the value asked for,
    the largest allowed, and the largest square image that fits."""
    host_memory = available_host_memory()
    excess = _first_excess(context, image_needs(context, width, height, guides, integrator), host_memory)
    if excess is None:
        return
    need, allowed = excess
    offered_by = "this host" if need.limit == HOST_MEMORY else f"the adapter {context.adapter_name}"
    side = _largest_square(context, host_memory, guides, integrator)
    guided = " with guides" if guides else ""
    guided += f" under {integrator.name}" if integrator is not None and integrator.pixel_arrays else ""
    raise DeviceLimitError(
        f"a {width:,}x{height:,} image: {need.what} needs {need.limit} = {need.value:,} but {offered_by} "
        f"offers {allowed:,}; the largest square image it can render{guided} is {side:,}x{side:,}"
    )


@dataclass(frozen=True)
class SceneCounts:
    """What a scene's GPU records number, known before its BVH is built."""

    triangles: int
    shapes: int
    materials: int
    emissive_triangles: int
    light_sources: int = 0
    environment: bool = False
    # an environment map's width and height (0 x 0: none, or a constant)
    environment_map: tuple[int, int] = (0, 0)
    # triangles of shapes with per-vertex normals (their vertex normals: `shading_normals_hook`)
    smooth_triangles: int = 0
    # triangles of shapes with vertex colours (their vertex colours: `vertex_colors_hook`)
    colored_triangles: int = 0

    @property
    def light_table_entries(self) -> int:
        return self.emissive_triangles + self.light_sources + int(self.environment)


def scene_counts(scene: Scene) -> SceneCounts:
    emitters = set(emitting_kinds())
    environment = scene.environment
    texels = None if environment is None else environment.texels
    # the instanced meshes' triangles are stored once each, after the shapes'
    stored = [*scene.shapes, *{id(instance.mesh): instance.mesh for instance in scene.instances}.values()]
    return SceneCounts(
        triangles=sum(shape.triangle_count for shape in stored),
        shapes=len(scene.shapes),
        materials=len(scene.materials),
        emissive_triangles=sum(shape.triangle_count for shape in scene.shapes if shape.material.kind in emitters),
        light_sources=len(scene.lights),
        environment=environment is not None,
        environment_map=(0, 0) if texels is None else (texels.shape[1], texels.shape[0]),
        smooth_triangles=sum(shape.triangle_count for shape in stored if shape.normals is not None),
        colored_triangles=sum(shape.triangle_count for shape in stored if shape.colors is not None),
    )


def environment_table_words(width: int, height: int) -> int:
    """32-bit words of an environment map's sampling tables (as `environment_table_words` packs them)."""
    rows = max(height - 1, 1)
    return 2 * rows + 3 * rows * width


def wide_record_bound(triangle_count: int) -> int:
    """At most this many 4-wide BVH records (`WideBVH`) for a tree over `triangle_count` triangles:
    one for a tree that is a single leaf, else (n - 1) // 3, as the comment below shows and
    `test_wide_record_bound_holds_for_built_trees` checks on built trees, lopsided ones too.
    """
    # Leaves are never empty and every binary interior node holds more than max_leaf_size = 4
    # triangles (the renderer builds with the default; any size >= 3 does). A record is an interior
    # node that adopted 2, 1 or 0 more (4, 3 or 2 children); one with fewer than 4 has only leaves
    # below it, so it holds its own node with two leaf children. With I interior nodes, R4 + R3 + R2
    # records and b nodes with two leaf children: I = 3 R4 + 2 R3 + R2, so R <= (I + 2b)/3; those b
    # nodes' leaves hold >= 5 triangles and every other leaf >= 1, so I <= n - 3b - 1, and
    # R <= (n - 1 - b)/3.
    return max(1, (triangle_count - 1) // 3)


def check_scene_counts(context: GpuContext, counts: SceneCounts, acceleration: str = "bvh") -> None:
    """DeviceLimitError if records of these counts exceed a limit: triangles and BVH records as
    texels, the flat list's boxes, materials and lights in storage buffers."""
    require_texels(context, "triangles", counts.triangles, TRIANGLE.dtype)
    storage = "max-storage-buffer-binding-size"
    if acceleration == "bvh":
        require_texels(context, "bvh nodes", wide_record_bound(counts.triangles), WIDE_BVH_NODE.dtype)
    else:
        require_records(context, "bvh nodes", counts.shapes, BVH_NODE.size, storage)
    require_records(context, "materials", counts.materials, MATERIAL.size, storage)
    require_records(context, "lights", counts.light_table_entries, LIGHT.size, storage)
    if counts.light_sources or counts.environment:
        context.require(
            "max-bind-groups", LIGHTS_GROUP_INDEX + 1, f"the lights group (bind group {LIGHTS_GROUP_INDEX})"
        )
    require_records(context, "light sources", counts.light_sources, LIGHT_SOURCE.size, storage)
    if counts.smooth_triangles or counts.colored_triangles:
        context.require(
            "max-bind-groups", SHADING_GROUP_INDEX + 1, f"the shading group (bind group {SHADING_GROUP_INDEX})"
        )
    if counts.smooth_triangles or counts.colored_triangles:
        # every triangle names its vertices, of which there are at most three per triangle (fewer
        # where corners share them: `shared_vertices`); every triangle has vertices once one shape
        # is smooth (a flat one's, zero normals) or has colours (a shape without, white)
        require_records(context, "triangle vertices", counts.triangles, TRIANGLE_VERTICES.size, storage)
    if counts.smooth_triangles:
        require_records(context, "vertex normals", 3 * counts.triangles, VERTEX_NORMAL.size, storage)
    if counts.colored_triangles:
        require_records(context, "vertex colors", 3 * counts.triangles, VERTEX_COLOR.size, storage)
    width, height = counts.environment_map
    if width:
        require_float_texture(context, "environment map", width, height)
        words = environment_table_words(width, height)
        require_records(context, "environment tables", words, np.dtype(np.uint32).itemsize, storage)


def atlas_side(context: GpuContext) -> int:
    """The texture atlas's largest side on this device (`fitted_texels` fits textures to it)."""
    return context.device.limits["max-texture-dimension-2d"]


def fit_environment(context: GpuContext, scene: Scene) -> None:
    """Replace an environment map larger than the adapter holds (its texture side, or its sampling
    tables in one storage binding: 8k maps exceed lavapipe's 128 MiB) by a box-filtered copy that
    fits, keeping its mean, with an EnvironmentWarning naming both sizes (`Environment.fit_to`):
    refusing the HDR maps users download would serve them worse than a softer sky."""
    environment = scene.environment
    if environment is None or environment.texels is None:
        return
    side = context.device.limits["max-texture-dimension-2d"]
    words = context.device.limits["max-storage-buffer-binding-size"] // np.dtype(np.uint32).itemsize
    # environment_table_words(w, h) <= 3 w h + 2 h: the cells the tables hold beside their rows
    fitted = environment.fit_to(side, side, max(1, (words - 2 * side) // 3))
    if fitted is not environment:
        scene.environment = fitted


def check_scene_size(context: GpuContext, scene: Scene, acceleration: str = "bvh") -> None:
    """DeviceLimitError, before the BVH is built, if the scene's records cannot fit the adapter,
    naming the texture or buffer, the limit, the value asked for and how many records it allows."""
    check_scene_counts(context, scene_counts(scene), acceleration)
