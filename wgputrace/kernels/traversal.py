"""The traversal a kernel compiles in: the acceleration structure's traversal file (the virtual file
`acceleration.wgsl` includes it) and the size of its per-ray stack."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..bvh.wide import STACK_SIZE as WIDE_STACK_SIZE
from .instancing import traversal_file

if TYPE_CHECKING:
    from .variant import KernelVariant

GENERATED_ACCELERATION = "generated/acceleration.wgsl"
GENERATED_TRAVERSAL_STACK = "generated/traversal_stack.wgsl"
# Entries of the per-ray traversal stack: enough for every tree the renderer builds (`WideBVH`
# says why), and more than the binary traversal of those trees needs.
BVH_STACK_SIZE = WIDE_STACK_SIZE
# The renderer compiles the stack only as large as its tree needs, rounded up to a multiple of
# this, so that an invocation's private memory stays small (on a GPU a large private array costs
# occupancy or spills; `python -m bench.kernel_profile --variants max_stack` measures it, bench's
# log has the figures). Rounding keeps the compiles few as edits change the tree.
STACK_SIZE_STEP = 16


def traversal_stack_size(entries_needed: int) -> int:
    """The stack size compiled for a tree whose traversal holds at most `entries_needed` entries."""
    if entries_needed > BVH_STACK_SIZE:
        raise ValueError(f"a traversal stack of {entries_needed} entries exceeds BVH_STACK_SIZE = {BVH_STACK_SIZE}")
    rounded = -(-max(entries_needed, 1) // STACK_SIZE_STEP) * STACK_SIZE_STEP
    return min(rounded, BVH_STACK_SIZE)


def traversal_stack(entries: int = BVH_STACK_SIZE) -> str:
    """The WGSL sizing the BVH traversal's stack."""
    return f"const TRAVERSAL_STACK_SIZE: u32 = {entries}u;\n"


def acceleration_hook(variant: KernelVariant) -> str:
    return f'//! include "geometry/traverse_{traversal_file(variant)}.wgsl"\n'


def traversal_stack_hook(variant: KernelVariant) -> str:
    return traversal_stack(variant.scene.stack_size)
