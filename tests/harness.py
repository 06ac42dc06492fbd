"""A small WGSL harness: run shipped shader functions on arrays and read the results back.

A test writes a kernel body that includes the shipped .wgsl files it exercises, reads its inputs
from `inputs_N` and writes `output`; the harness binds numpy arrays to them, dispatches one
invocation per element, and returns the output array. The shipped code is what is tested.
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgputrace.gpu.buffers import read_buffer, storage_buffer, uniform_buffer
from wgputrace.gpu.graphics import read_texture
from wgputrace.gpu.layout import FRAME
from wgputrace.gpu.pipeline import compute_kernel
from wgputrace.gpu.shader_source import shader_root
from wgputrace.gpu.texels import TrackedTexels
from wgputrace.render.scene_buffers import SceneRecords

HARNESS_GROUP = 1
# bindings of group 0 that are not storage buffers (scene_bindings.wgsl)
FRAME_BINDING, TRIANGLE_BINDING = 0, 1
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
    scene: dict[int, np.ndarray | object] | None = None,
) -> np.ndarray:
    """Run `wgsl` (which defines `fn compute(i: u32) -> OUTPUT`) for i in [0, count).

    inputs[k] is bound read-only as `inputs_k: array<input_types[k]>` in group 1; `scene`, if
    given, fills group 0 as scene_bindings.wgsl declares it (0 = Frame record, 1 = triangles,
    2 = nodes, 3 = materials): arrays are uploaded (the triangles as texels), GPU resources
    (`node_binding`) bound as they are.
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
        scene_resources = {b: _scene_resource(context, b, a) for b, a in scene.items()}
        compute.set_bind_group(0, kernel.bind_group(context, 0, scene_resources))
    compute.set_bind_group(HARNESS_GROUP, kernel.bind_group(context, HARNESS_GROUP, buffers))
    compute.dispatch_workgroups(-(-count // WORKGROUP), 1, 1)
    compute.end()
    device.queue.submit([encoder.finish()])
    return read_buffer(context, result, output_dtype, count)


def _scene_resource(context, binding: int, value):
    if not isinstance(value, np.ndarray):
        return value
    if binding == FRAME_BINDING:
        return uniform_buffer(context, "frame", value)
    if binding == TRIANGLE_BINDING:
        return TrackedTexels(context, "triangles", value).resource
    return storage_buffer(context, f"scene {binding}", value)


def node_binding(context, records: SceneRecords) -> np.ndarray | wgpu.GPUTextureView:
    """Binding 2 as the traversal `records` were built for reads it: the BVH's nodes as texels
    (traverse_bvh.wgsl), the flat list's boxes as a storage buffer (traverse_flat.wgsl)."""
    if records.acceleration.kind == "bvh":
        return TrackedTexels(context, "nodes", records.nodes).resource
    return records.nodes


def read_binding(context, resource, dtype: np.dtype, count: int) -> np.ndarray:
    """The first `count` records of a bound buffer or texel texture (gpu/texels.py)."""
    if isinstance(resource, wgpu.GPUBuffer):
        return read_buffer(context, resource, dtype, count)
    texels = read_texture(context, resource.texture, np.uint32, 4)
    # a texture of 3-texel records need not hold a whole number of them: cut before viewing
    return np.frombuffer(texels.tobytes()[: count * dtype.itemsize], dtype).copy()


def frame_record(node_count: int = 0) -> np.ndarray:
    record = FRAME.zeros(1)
    record["node_count"] = node_count
    return record


__all__ = ["run_kernel", "frame_record", "node_binding", "read_binding", "shader_root"]
