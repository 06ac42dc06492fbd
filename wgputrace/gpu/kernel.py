"""Kernels: a shader file compiled against declared bind groups (`BindGroup`), with compile
errors that name the original .wgsl file and line, bind groups made by binding name, and for
compute kernels the one place that encodes, dispatches and submits."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import wgpu

from .bindings import GENERATED_WORKGROUP, IMAGE_WORKGROUP, BindGroup, group_files, workgroup_constants
from .device import GpuContext
from .shader_source import ShaderSource, load_shader


class ShaderCompileError(RuntimeError):
    """The WGSL did not compile; the message names the original .wgsl file and line."""


class Kernel:
    """What compute and render kernels share: the joined source, the declared groups by name, and
    bind groups made by binding name."""

    pipeline: wgpu.GPUComputePipeline | wgpu.GPURenderPipeline

    def __init__(self, context: GpuContext, source: ShaderSource, groups: Sequence[BindGroup], label: str) -> None:
        self.context, self.source, self.label = context, source, label
        self.groups = {group.name: group for group in groups}

    def bind(self, group: str, **resources: object) -> wgpu.GPUBindGroup:
        """A bind group of `group` (a declared group's name) from resources by binding name."""
        return self.group(group).create(self.context, resources)

    def group(self, name: str) -> BindGroup:
        if name not in self.groups:
            raise KeyError(f"kernel {self.label!r} declares no bind group {name!r} (it has {', '.join(self.groups)})")
        return self.groups[name]

    def set_bind_groups(self, encoder, bind_groups: Mapping[str, wgpu.GPUBindGroup]) -> None:
        """Set the pipeline and every declared group, from `bind_groups` by group name, on a
        compute or render pass `encoder`."""
        missing = [name for name in self.groups if name not in bind_groups]
        if missing:
            raise KeyError(f"kernel {self.label!r} needs bind groups {', '.join(missing)}")
        encoder.set_pipeline(self.pipeline)
        for name, group in self.groups.items():
            encoder.set_bind_group(group.index, bind_groups[name])


def compile_shader(
    context: GpuContext,
    entry: str,
    groups: Sequence[BindGroup],
    generated: dict[str, str] | None,
    label: str,
    create_pipeline,
) -> tuple[ShaderSource, object]:
    """Join `entry` with the groups' declarations and the `generated` files; compile it and call
    `create_pipeline(module, layout)` with the layout made of `groups`."""
    layout = pipeline_layout(context, groups, label)
    source = load_shader(entry, {**group_files(tuple(groups)), **(generated or {})})
    try:
        module = context.device.create_shader_module(label=label, code=source.text)
        return source, create_pipeline(module, layout)
    except wgpu.GPUError as error:
        raise ShaderCompileError(source.explain(str(error))) from None


def pipeline_layout(context: GpuContext, groups: Sequence[BindGroup], label: str) -> wgpu.GPUPipelineLayout:
    """The explicit layout of `groups` (indices they do not use get an empty group)."""
    by_index = {}
    for group in groups:
        if group.index in by_index:
            raise ValueError(
                f"{label}: bind groups {by_index[group.index].name!r} and {group.name!r} share index {group.index}"
            )
        by_index[group.index] = group
    count = max(by_index, default=-1) + 1
    layouts = [by_index.get(i, BindGroup("empty", i, ())).layout(context) for i in range(count)]
    return context.device.create_pipeline_layout(label=label, bind_group_layouts=layouts)


class ComputeKernel(Kernel):
    """A compute pipeline, its workgroup size (the shader reads it as WORKGROUP_X, WORKGROUP_Y) and its groups."""

    def __init__(
        self,
        context: GpuContext,
        entry: str,
        groups: Sequence[BindGroup] = (),
        *,
        workgroup_size: tuple[int, int] = IMAGE_WORKGROUP,
        generated: dict[str, str] | None = None,
        constants: dict[str, float | int | bool] | None = None,
        label: str | None = None,
        entry_point: str = "main",
    ) -> None:
        """Compile `entry` (a file under shaders/, or a virtual one in `generated`) at `entry_point`,
        with the virtual files `generated` (a kernel variant's: `compute_kernel`)."""
        label = label or entry

        def create(module, layout):
            compute = {"module": module, "entry_point": entry_point, "constants": constants or {}}
            return context.device.create_compute_pipeline(label=label, layout=layout, compute=compute)

        files = {GENERATED_WORKGROUP: workgroup_constants(workgroup_size), **(generated or {})}
        source, self.pipeline = compile_shader(context, entry, groups, files, label, create)
        super().__init__(context, source, groups, label)
        self.workgroup_size = workgroup_size

    def workgroups(self, size: Sequence[int]) -> tuple[int, int, int]:
        """Workgroups covering `size` invocations: (count,) or (width, height)."""
        width, height = (*size, 1)[:2]
        return (-(-width // self.workgroup_size[0]), -(-height // self.workgroup_size[1]), 1)

    def dispatch(
        self, size: Sequence[int], bind_groups: Mapping[str, wgpu.GPUBindGroup], *, repeat: int = 1, wait: bool = False
    ) -> None:
        """Run over `size` invocations `repeat` times in one submit; `wait` until the adapter is done."""
        submit(self.context, [Pass(self, tuple(size), bind_groups)] * repeat, wait=wait)


@dataclass(frozen=True)
class Pass:
    """One dispatch of `kernel` over `size` invocations with `bind_groups` by group name."""

    kernel: ComputeKernel
    size: tuple[int, ...]
    bind_groups: Mapping[str, wgpu.GPUBindGroup]


class Timestamps:
    """GPU timestamps around the last pass of a submit (adapters with "timestamp-query")."""

    def __init__(self, context: GpuContext) -> None:
        self.context = context
        self.query_set = context.device.create_query_set(type=wgpu.QueryType.timestamp, count=2)
        self.buffer = context.device.create_buffer(
            size=16, usage=wgpu.BufferUsage.QUERY_RESOLVE | wgpu.BufferUsage.COPY_SRC
        )

    @property
    def writes(self) -> dict:
        return {"query_set": self.query_set, "beginning_of_pass_write_index": 0, "end_of_pass_write_index": 1}

    def seconds(self) -> float:
        """The last measured pass's time (WebGPU resolves timestamps to nanoseconds)."""
        ticks = np.frombuffer(self.context.device.queue.read_buffer(self.buffer), np.uint64)
        return float(ticks[1] - ticks[0]) * 1e-9


def submit(
    context: GpuContext, passes: Sequence[Pass], *, wait: bool = False, timestamps: Timestamps | None = None
) -> None:
    """Encode `passes` in order into one command buffer and submit it; `wait` for the adapter;
    `timestamps` time the last pass."""
    encoder = context.device.create_command_encoder()
    for number, step in enumerate(passes, start=1):
        writes = timestamps.writes if timestamps is not None and number == len(passes) else None
        compute = encoder.begin_compute_pass(timestamp_writes=writes)
        step.kernel.set_bind_groups(compute, step.bind_groups)
        compute.dispatch_workgroups(*step.kernel.workgroups(step.size))
        compute.end()
    if timestamps is not None:
        encoder.resolve_query_set(timestamps.query_set, 0, 2, timestamps.buffer, 0)
    context.submit(encoder, ", ".join(dict.fromkeys(step.kernel.label for step in passes)))
    if wait:
        context.finish()
