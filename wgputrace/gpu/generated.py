"""The generated files every kernel includes: structs, ids and constants made from the Python definitions."""

from __future__ import annotations

from ..bvh.wide import STACK_SIZE as WIDE_STACK_SIZE
from ..bvh.wide import WIDE_COUNT_BITS, WIDE_EMPTY, WIDE_LEAF, WIDE_LEAF_MAX
from .alpha import GENERATED_ALPHA, alpha_hook
from .emission import GENERATED_EMISSION, emission_hook
from .layout import ALL_STRUCTS
from .light_dispatch import (
    GENERATED_ESCAPED_LIGHT,
    GENERATED_LIGHTS,
    escaped_light_hook,
    light_dispatch,
    light_kind_constants,
)
from .material_dispatch import GENERATED_MATERIALS, material_dispatch, material_kind_constants
from .path_guides import GENERATED_PATH_GUIDES, path_guides_hook
from .ray_count import GENERATED_RAY_COUNT, ray_count_hook
from .sampler import DEFAULT_SAMPLER, GENERATED_SAMPLER, sampler_hook
from .shading_normals import GENERATED_SHADING_NORMALS, shading_normals_hook
from .texels import GENERATED_TEXEL_LOADERS, TEXEL_STRUCTS, texel_loaders
from .textures import GENERATED_TEXTURES, textures_hook

GENERATED_STRUCTS = "generated/structs.wgsl"

# Marks "no triangle" in hit records and "skip nothing" in traversal.
NO_TRIANGLE = 0xFFFFFFFF
# The path tracer's estimators of direct light, in the order of their ids in the shaders
# (INTEGRATOR_BSDF = 0, ...), and every integrator: those and bidirectional path tracing (its own
# kernel, shaders/integrators/bdpt.wgsl).
PATH_TRACER_INTEGRATORS = ("bsdf", "nee", "mis")
INTEGRATORS = (*PATH_TRACER_INTEGRATORS, "bdpt")
# Entries of the per-ray traversal stack: enough for every tree the renderer builds (bvh/wide.py
# says why), and more than the binary traversal of those trees needs.
BVH_STACK_SIZE = WIDE_STACK_SIZE
# The renderer compiles the stack only as large as its tree needs, rounded up to a multiple of
# this, so that an invocation's private memory stays small (on a GPU a large private array costs
# occupancy or spills; `python -m bench.kernel_profile --variants max_stack` measures it on this
# adapter, bench/README.md's log has the figures). Rounding keeps the compiles few as edits change
# the tree.
STACK_SIZE_STEP = 16
GENERATED_TRAVERSAL_STACK = "generated/traversal_stack.wgsl"


def traversal_stack_size(entries_needed: int) -> int:
    """The stack size compiled for a tree whose traversal holds at most `entries_needed` entries."""
    if entries_needed > BVH_STACK_SIZE:
        raise ValueError(f"a traversal stack of {entries_needed} entries exceeds BVH_STACK_SIZE = {BVH_STACK_SIZE}")
    rounded = -(-max(entries_needed, 1) // STACK_SIZE_STEP) * STACK_SIZE_STEP
    return min(rounded, BVH_STACK_SIZE)


def traversal_stack(entries: int = BVH_STACK_SIZE) -> str:
    """The generated file sizing geometry/traverse_bvh.wgsl's stack."""
    return f"const TRAVERSAL_STACK_SIZE: u32 = {entries}u;\n"


def generated_structs() -> str:
    """Struct definitions and shared constants, made from the Python definitions."""
    parts = ["// Generated from wgputrace.gpu.layout and wgputrace.scene: host/GPU structs and ids."]
    parts += [struct.wgsl() for struct in ALL_STRUCTS]
    parts += material_kind_constants()
    parts += light_kind_constants()
    parts += [f"const INTEGRATOR_{name.upper()}: u32 = {index}u;" for index, name in enumerate(PATH_TRACER_INTEGRATORS)]
    parts.append(f"const NO_TRIANGLE: u32 = {NO_TRIANGLE:#x}u;")
    parts.append(f"const BVH_STACK_SIZE: u32 = {BVH_STACK_SIZE}u;")
    parts.append(f"const WIDE_LEAF: u32 = {WIDE_LEAF:#x}u;")
    parts.append(f"const WIDE_COUNT_BITS: u32 = {WIDE_COUNT_BITS}u;")
    parts.append(f"const WIDE_COUNT_MASK: u32 = {WIDE_LEAF_MAX - 1}u;")
    parts.append(f"const WIDE_EMPTY: u32 = {WIDE_EMPTY:#x}u;")
    return "\n".join(parts) + "\n"


def standard_files() -> dict[str, str]:
    """The generated files every kernel gets unless it replaces them: structs and ids, the material
    dispatch for every kind, no lights besides emissive triangles, no ray counting, no denoiser
    guides, flat shading, no textures, every surface opaque and emitting by its kind alone, the texel loaders, the largest traversal stack and the default sampler."""
    return {
        GENERATED_STRUCTS: generated_structs(),
        GENERATED_MATERIALS: material_dispatch(),
        GENERATED_LIGHTS: light_dispatch(),
        GENERATED_ESCAPED_LIGHT: escaped_light_hook(),
        GENERATED_RAY_COUNT: ray_count_hook(counting=False),
        GENERATED_PATH_GUIDES: path_guides_hook(guides=False),
        GENERATED_SHADING_NORMALS: shading_normals_hook(smooth=False),
        GENERATED_TEXTURES: textures_hook(textured=False),
        GENERATED_ALPHA: alpha_hook(see_through=False),
        GENERATED_EMISSION: emission_hook(emissive=False),
        GENERATED_TEXEL_LOADERS: texel_loaders(TEXEL_STRUCTS),
        GENERATED_TRAVERSAL_STACK: traversal_stack(),
        GENERATED_SAMPLER: sampler_hook(DEFAULT_SAMPLER),
    }
