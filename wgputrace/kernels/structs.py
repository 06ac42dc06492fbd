"""The generated file every kernel includes: the host/GPU structs and the ids and constants of
material kinds, light kinds, the path tracer's estimators and the wide BVH's encoding."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..bvh.wide import WIDE_COUNT_BITS, WIDE_EMPTY, WIDE_LEAF, WIDE_LEAF_MAX
from ..gpu.layout import ALL_STRUCTS
from .light_dispatch import light_kind_constants
from .material_dispatch import material_kind_constants
from .traversal import BVH_STACK_SIZE

if TYPE_CHECKING:
    from .variant import KernelVariant

GENERATED_STRUCTS = "generated/structs.wgsl"

# Marks "no triangle" in hit records and "skip nothing" in traversal.
NO_TRIANGLE = 0xFFFFFFFF
# The path tracer's estimators of direct light, in the order of their ids in the shaders
# (INTEGRATOR_BSDF = 0, ...): the `PathTracer` integrators choose one by the override INTEGRATOR.
ESTIMATORS = ("bsdf", "nee", "mis")


def generated_structs() -> str:
    """Struct definitions and shared constants, made from the Python definitions."""
    parts = ["// Generated from wgputrace.gpu.layout and wgputrace.scene: host/GPU structs and ids."]
    parts += [struct.wgsl() for struct in ALL_STRUCTS]
    parts += material_kind_constants()
    parts += light_kind_constants()
    parts += [f"const INTEGRATOR_{name.upper()}: u32 = {index}u;" for index, name in enumerate(ESTIMATORS)]
    parts.append(f"const NO_TRIANGLE: u32 = {NO_TRIANGLE:#x}u;")
    parts.append(f"const BVH_STACK_SIZE: u32 = {BVH_STACK_SIZE}u;")
    parts.append(f"const WIDE_LEAF: u32 = {WIDE_LEAF:#x}u;")
    parts.append(f"const WIDE_COUNT_BITS: u32 = {WIDE_COUNT_BITS}u;")
    parts.append(f"const WIDE_COUNT_MASK: u32 = {WIDE_LEAF_MAX - 1}u;")
    parts.append(f"const WIDE_EMPTY: u32 = {WIDE_EMPTY:#x}u;")
    return "\n".join(parts) + "\n"


def structs_hook(variant: KernelVariant) -> str:
    return generated_structs()
