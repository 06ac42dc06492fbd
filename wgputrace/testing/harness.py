"""A small WGSL harness: run shipped shader functions on arrays and read the results back.

A test writes a kernel body that includes the shipped .wgsl files it exercises, reads its inputs
from `inputs_N` and writes `output`; the harness binds numpy arrays to them (the "harness" group,
declared like every other in gpu/bindings.py), dispatches one invocation per element, and returns
the output array. The scene group is declared too, so the body may include geometry/scene_bindings.wgsl or
a traversal: the scene resources a test gives go by binding name, the others hold one zero record.
The shipped code is what is tested.
"""

from __future__ import annotations

import numpy as np
import wgpu

from wgputrace.gpu.bindings import (
    ARRAY_WORKGROUP,
    SCENE_GROUP,
    STORAGE_READ,
    STORAGE_READ_WRITE,
    BindGroup,
    Binding,
    scene_group,
)
from wgputrace.gpu.buffers import read_buffer, storage_buffer, uniform_buffer
from wgputrace.gpu.graphics import read_texture
from wgputrace.gpu.kernel import ComputeKernel
from wgputrace.gpu.layout import BVH_NODE, FRAME, LIGHT, MATERIAL, TRIANGLE, WIDE_BVH_NODE
from wgputrace.gpu.texels import TrackedTexels
from wgputrace.render.scene_buffers import SceneRecords

# Invocations per workgroup: a dispatch holds at most 65,535 times this many.
WORKGROUP = ARRAY_WORKGROUP[0]
# What each scene binding holds when a test gives nothing for it (texels for the triangles and the
# BVH's nodes, a buffer for the rest).
_SCENE_RECORDS = {"triangles": TRIANGLE, "materials": MATERIAL, "lights": LIGHT}
_NODE_RECORDS = {"bvh": WIDE_BVH_NODE, "flat": BVH_NODE}


def harness_group(input_types: list[str], output_type: str) -> BindGroup:
    """The harness's inputs (`inputs_k: array<input_types[k]>`, read-only) and its `output`."""
    inputs = [Binding(f"inputs_{k}", STORAGE_READ, t) for k, t in enumerate(input_types)]
    return BindGroup("harness", SCENE_GROUP.index + 1, (*inputs, Binding("output", STORAGE_READ_WRITE, output_type)))


def run_kernel(
    context,
    wgsl: str,
    inputs: list[np.ndarray],
    output_dtype: np.dtype,
    count: int,
    *,
    input_types: list[str],
    output_type: str,
    scene: dict[str, np.ndarray | object] | None = None,
    groups: dict[BindGroup, dict[str, object]] | None = None,
    generated: dict[str, str] | None = None,
) -> np.ndarray:
    """Run `wgsl` (which defines `fn compute(i: u32) -> OUTPUT`) for i in [0, count).

    inputs[k] is bound read-only as `inputs_k: array<input_types[k]>`. `scene` fills the scene
    group (gpu/bindings.py SCENE_GROUP) by binding name: frame, triangles, nodes, materials, lights.
    Arrays are uploaded (the triangles as texels), GPU resources (`node_binding`) bound as they
    are; nodes given as an array are the flat list's storage buffer, else the BVH's texels.
    `groups` adds bind groups (the lights group, say) with their GPU resources by binding name, and
    `generated` the generated files their WGSL includes (the light dispatch).
    """
    groups = dict(groups or {})
    scene = dict(scene or {})
    acceleration = "flat" if isinstance(scene.get("nodes"), np.ndarray) else "bvh"
    harness = harness_group(input_types, output_type)
    entry = "\n".join(
        [
            wgsl,
            f'//! include "{harness.file}"',
            '//! include "generated/workgroup.wgsl"',
            "@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)",
            "fn main(@builtin(global_invocation_id) id: vec3<u32>) {",
            f"    if id.x >= {count}u {{ return; }}",
            "    output[id.x] = compute(id.x);",
            "}",
        ]
    )
    kernel = ComputeKernel(
        context,
        "harness_entry.wgsl",
        (scene_group(acceleration), harness, *groups),
        workgroup_size=ARRAY_WORKGROUP,
        generated={"harness_entry.wgsl": entry, **(generated or {})},
        label="test harness",
    )
    result = storage_buffer(context, "output", np.zeros(count, dtype=output_dtype), read_back=True)
    buffers = {f"inputs_{k}": storage_buffer(context, f"input {k}", a) for k, a in enumerate(inputs)}
    scene_resources = _scene_resources(context, scene, acceleration)
    bind_groups = {
        "scene": kernel.bind("scene", **scene_resources),
        "harness": kernel.bind("harness", **buffers, output=result),
        **{group.name: kernel.bind(group.name, **resources) for group, resources in groups.items()},
    }
    kernel.dispatch((count,), bind_groups)
    return read_buffer(context, result, output_dtype, count)


def _scene_resources(context, scene: dict[str, object], acceleration: str) -> dict[str, object]:
    records = {**_SCENE_RECORDS, "nodes": _NODE_RECORDS[acceleration]}
    given = {"frame": frame_record(), **{name: struct.zeros(1) for name, struct in records.items()}, **scene}
    resources = {}
    for name, value in given.items():
        if not isinstance(value, np.ndarray):
            resources[name] = value
        elif name == "frame":
            resources[name] = uniform_buffer(context, "frame", value)
        elif name == "triangles" or (name == "nodes" and acceleration == "bvh"):
            resources[name] = TrackedTexels(context, name, value).resource
        else:
            resources[name] = storage_buffer(context, f"scene {name}", value)
    return resources


def node_binding(context, records: SceneRecords) -> np.ndarray | wgpu.GPUTextureView:
    """The scene group's `nodes` as the traversal `records` were built for reads them: the BVH's
    records as texels (geometry/traverse_bvh.wgsl), the flat list's boxes as an array for a storage buffer
    (geometry/traverse_flat.wgsl)."""
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


__all__ = ["WORKGROUP", "frame_record", "harness_group", "node_binding", "read_binding", "run_kernel"]
