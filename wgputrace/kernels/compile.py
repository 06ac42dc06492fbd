"""Kernels compiled for a KernelVariant: any entry file with the variant's generated files
(`compute_kernel`), and an integrator's own kernel, cached per device and variant (`tracing_kernel`)."""

from __future__ import annotations

from collections.abc import Sequence

from ..gpu.bindings import BindGroup
from ..gpu.device import GpuContext
from ..gpu.kernel import ComputeKernel
from .variant import DEFAULT_VARIANT, KernelVariant

_kernels: dict[tuple[int, KernelVariant], ComputeKernel] = {}


def compute_kernel(
    context: GpuContext,
    entry: str,
    groups: Sequence[BindGroup] = (),
    variant: KernelVariant = DEFAULT_VARIANT,
    *,
    generated: dict[str, str] | None = None,
    **options,
) -> ComputeKernel:
    """`entry` compiled with `variant`'s generated files, `generated` added or replacing some;
    `options` are ComputeKernel's (workgroup_size, constants, label, entry_point)."""
    return ComputeKernel(context, entry, groups, generated={**variant.files(), **(generated or {})}, **options)


def tracing_kernel(context: GpuContext, variant: KernelVariant) -> ComputeKernel:
    """The integrator's kernel for `variant` (its band-of-rows entry with `rows`), compiled once per
    device and variant."""
    key = (id(context.device), variant)
    if key not in _kernels:
        entry, entry_point = variant.entry
        _kernels[key] = compute_kernel(
            context,
            entry,
            variant.groups(),
            variant,
            constants=variant.constants,
            label=f"{variant.integrator.name} ({variant.label})",
            entry_point=entry_point,
        )
    return _kernels[key]
