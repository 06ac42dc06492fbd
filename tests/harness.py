"""A small WGSL harness: run shipped shader functions on arrays and read the results back.

A test writes a kernel body that includes the shipped .wgsl files it exercises, reads its inputs
from `inputs_N` and writes `output`; the harness binds numpy arrays to them, dispatches one
invocation per element, and returns the output array. The shipped code is what is tested.
"""

from __future__ import annotations

import numpy as np

from wgputrace.gpu.buffers import read_buffer, storage_buffer, uniform_buffer
from wgputrace.gpu.layout import FRAME
from wgputrace.gpu.pipeline import compute_kernel
from wgputrace.gpu.shader_source import shader_root

HARNESS_GROUP = 1
WORKGROUP = 64


def run_kernel(
    context,
    wgsl: str,
    inputs: list[np.ndarray],
    output_dtype: np.dtype,
    count: int,
    *,
    input_types: list[str],
    output_type: str,
    scene: dict[int, np.ndarray] | None = None,
) -> np.ndarray:
    """Run `wgsl` (which defines `fn compute(i: u32) -> OUTPUT`) for i in [0, count).

    inputs[k] is bound read-only as `inputs_k: array<input_types[k]>` in group 1; `scene`, if
    given, fills group 0 as scene_bindings.wgsl declares it (0 = Frame record, 1 = triangles,
    2 = nodes, 3 = materials).
    """
    declarations = [
        f"@group({HARNESS_GROUP}) @binding({k}) var<storage, read> inputs_{k}: array<{t}>;"
        for k, t in enumerate(input_types)
    ]
    out_binding = len(inputs)
    declarations.append(
        f"@group({HARNESS_GROUP}) @binding({out_binding}) var<storage, read_write> output: array<{output_type}>;"
    )
    entry = "\n".join(
        [
            wgsl,
            *declarations,
            f"@compute @workgroup_size({WORKGROUP})",
            "fn main(@builtin(global_invocation_id) id: vec3<u32>) {",
            f"    if id.x >= {count}u {{ return; }}",
            "    output[id.x] = compute(id.x);",
            "}",
        ]
    )
    kernel = compute_kernel(
        context,
        "harness_entry.wgsl",
        generated={"harness_entry.wgsl": entry},
        workgroup_size=(WORKGROUP, 1),
        label="test harness",
    )
    device = context.device
    buffers = {k: storage_buffer(context, f"input {k}", a) for k, a in enumerate(inputs)}
    result = storage_buffer(context, "output", np.zeros(count, dtype=output_dtype), read_back=True)
    buffers[out_binding] = result
    encoder = device.create_command_encoder()
    compute = encoder.begin_compute_pass()
    compute.set_pipeline(kernel.pipeline)
    if scene:
        scene_buffers = {
            b: (uniform_buffer(context, "frame", a) if b == 0 else storage_buffer(context, f"scene {b}", a))
            for b, a in scene.items()
        }
        compute.set_bind_group(0, kernel.bind_group(context, 0, scene_buffers))
    compute.set_bind_group(HARNESS_GROUP, kernel.bind_group(context, HARNESS_GROUP, buffers))
    compute.dispatch_workgroups(-(-count // WORKGROUP), 1, 1)
    compute.end()
    device.queue.submit([encoder.finish()])
    return read_buffer(context, result, output_dtype, count)


def frame_record(node_count: int = 0) -> np.ndarray:
    record = FRAME.zeros(1)
    record["node_count"] = node_count
    return record


__all__ = ["run_kernel", "frame_record", "shader_root"]
