"""Compute pipelines built from shader files, with compile errors that name the original file."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from ..bvh.wide import STACK_SIZE as WIDE_STACK_SIZE
from ..bvh.wide import WIDE_COUNT_BITS, WIDE_EMPTY, WIDE_LEAF, WIDE_LEAF_MAX
from ..scene.materials import MaterialKind
from .device import GpuContext
from .layout import ALL_STRUCTS
from .material_dispatch import GENERATED_MATERIALS, material_dispatch
from .ray_count import GENERATED_RAY_COUNT, ray_count_hook
from .shader_source import ShaderSource, load_shader
from .texels import GENERATED_TEXEL_LOADERS, TEXEL_STRUCTS, texel_loaders

GENERATED_STRUCTS = "generated/structs.wgsl"

# Marks "no triangle" in hit records and "skip nothing" in traversal.
NO_TRIANGLE = 0xFFFFFFFF
# Estimators of direct light, in the order of their ids in the shaders (INTEGRATOR_BSDF = 0, ...).
INTEGRATORS = ("bsdf", "nee", "mis")
# Entries of the per-ray traversal stack: enough for every tree the renderer builds (bvh/wide.py
# says why), and more than the binary traversal of those trees needs.
BVH_STACK_SIZE = WIDE_STACK_SIZE
# The renderer compiles the stack only as large as its tree needs, rounded up to a multiple of
# this, so that an invocation's private memory stays small (on a GPU a large private array costs
# occupancy or spills). On lavapipe it mattered while the stack was a function variable, zero-filled
# at every traversal (the Cornell box at 0.61x with the largest stack); at module scope it no longer
# measurably does (`python bench/kernel_profile.py --variants max_stack`: x1.00, x0.99). Rounding
# keeps the compiles few as edits change the tree.
STACK_SIZE_STEP = 16
GENERATED_TRAVERSAL_STACK = "generated/traversal_stack.wgsl"


def traversal_stack_size(entries_needed: int) -> int:
    """The stack size compiled for a tree whose traversal holds at most `entries_needed` entries."""
    if entries_needed > BVH_STACK_SIZE:
        raise ValueError(f"a traversal stack of {entries_needed} entries exceeds BVH_STACK_SIZE = {BVH_STACK_SIZE}")
    rounded = -(-max(entries_needed, 1) // STACK_SIZE_STEP) * STACK_SIZE_STEP
    return min(rounded, BVH_STACK_SIZE)


def traversal_stack(entries: int = BVH_STACK_SIZE) -> str:
    """The generated file sizing traverse_bvh.wgsl's stack."""
    return f"const TRAVERSAL_STACK_SIZE: u32 = {entries}u;\n"


class ShaderCompileError(RuntimeError):
    """The WGSL did not compile; the message names the original .wgsl file and line."""


def generated_structs() -> str:
    """Struct definitions and shared constants, made from the Python definitions."""
    parts = ["// Generated from wgputrace.gpu.layout and wgputrace.scene: host/GPU structs and ids."]
    parts += [struct.wgsl() for struct in ALL_STRUCTS]
    parts += [f"const MATERIAL_{kind.name}: u32 = {int(kind)}u;" for kind in MaterialKind]
    parts += [f"const INTEGRATOR_{name.upper()}: u32 = {index}u;" for index, name in enumerate(INTEGRATORS)]
    parts.append(f"const NO_TRIANGLE: u32 = {NO_TRIANGLE:#x}u;")
    parts.append(f"const BVH_STACK_SIZE: u32 = {BVH_STACK_SIZE}u;")
    parts.append(f"const WIDE_LEAF: u32 = {WIDE_LEAF:#x}u;")
    parts.append(f"const WIDE_COUNT_BITS: u32 = {WIDE_COUNT_BITS}u;")
    parts.append(f"const WIDE_COUNT_MASK: u32 = {WIDE_LEAF_MAX - 1}u;")
    parts.append(f"const WIDE_EMPTY: u32 = {WIDE_EMPTY:#x}u;")
    return "\n".join(parts) + "\n"


@dataclass
class ComputeKernel:
    pipeline: wgpu.GPUComputePipeline
    source: ShaderSource
    workgroup_size: tuple[int, int]

    def bind_group(self, context: GpuContext, group: int, resources: dict[int, object]) -> wgpu.GPUBindGroup:
        """Bind buffers (whole) and texture views (binding -> resource) to `group`."""
        return context.device.create_bind_group(
            layout=self.pipeline.get_bind_group_layout(group),
            entries=[{"binding": b, "resource": binding_resource(r)} for b, r in resources.items()],
        )


def binding_resource(resource: object) -> object:
    """What a bind group entry takes for a buffer (all of it) or a texture view (itself)."""
    if isinstance(resource, wgpu.GPUBuffer):
        return {"buffer": resource, "offset": 0, "size": resource.size}
    return resource


def compute_kernel(
    context: GpuContext,
    entry: str,
    *,
    generated: dict[str, str] | None = None,
    constants: dict[str, float | int | bool] | None = None,
    workgroup_size: tuple[int, int] = (8, 8),
    label: str | None = None,
    entry_point: str = "main",
) -> ComputeKernel:
    """Compile `entry` (a file under shaders/ with `fn main`, or the function `entry_point`) into a
    compute pipeline.

    `generated` adds or replaces virtual files; by default the material dispatch covers every kind,
    rays are not counted and the traversal stack has BVH_STACK_SIZE entries.
    """
    files = {
        GENERATED_STRUCTS: generated_structs(),
        GENERATED_MATERIALS: material_dispatch(),
        GENERATED_RAY_COUNT: ray_count_hook(counting=False),
        GENERATED_TEXEL_LOADERS: texel_loaders(TEXEL_STRUCTS),
        GENERATED_TRAVERSAL_STACK: traversal_stack(),
        **(generated or {}),
    }
    source = load_shader(entry, files)
    try:
        module = context.device.create_shader_module(label=label or entry, code=source.text)
        pipeline = context.device.create_compute_pipeline(
            label=label or entry,
            layout="auto",
            compute={"module": module, "entry_point": entry_point, "constants": constants or {}},
        )
    except wgpu.GPUError as error:
        raise ShaderCompileError(source.explain(str(error))) from None
    return ComputeKernel(pipeline, source, workgroup_size)


def dispatch_size(width: int, height: int, workgroup_size: tuple[int, int]) -> tuple[int, int, int]:
    return (-(-width // workgroup_size[0]), -(-height // workgroup_size[1]), 1)


def as_bytes(array: np.ndarray) -> memoryview:
    return memoryview(np.ascontiguousarray(array)).cast("B")
