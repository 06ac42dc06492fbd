"""A small WGSL harness: run shipped shader functions on arrays and read the results back.

A test writes a kernel body that includes the shipped .wgsl files it exercises, reads its inputs
from `inputs_N` and writes `output`; the harness binds numpy arrays to them (the "harness" group,
declared like every other bind group), dispatches one invocation per element, and returns
the output array. The scene group is declared too, so the body may include the scene bindings or
a traversal: the scene resources a test gives go by binding name, the others hold one zero record.
The shipped code is what is tested.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import wgpu

from wgputrace.gpu.bindings import ARRAY_WORKGROUP, STORAGE_READ, STORAGE_READ_WRITE, BindGroup, Binding
from wgputrace.gpu.buffers import read_buffer, storage_buffer, uniform_buffer
from wgputrace.gpu.graphics import read_texture
from wgputrace.gpu.layout import BVH_NODE, FRAME, LIGHT, MATERIAL, TRIANGLE, WIDE_BVH_NODE
from wgputrace.gpu.texels import TrackedTexels
from wgputrace.kernels.bind_groups import SCENE_GROUP, scene_group
from wgputrace.kernels.compile import compute_kernel
from wgputrace.kernels.variant import DEFAULT_VARIANT, KernelVariant
from wgputrace.render.scene_records import SceneRecords

# Invocations per workgroup: a dispatch holds at most 65,535 times this many.
WORKGROUP = ARRAY_WORKGROUP[0]
# What each scene binding holds when a test gives nothing for it (texels for the triangles and the
# BVH's nodes, a buffer for the rest).
_SCENE_RECORDS = {"triangles": TRIANGLE, "materials": MATERIAL, "lights": LIGHT}
_NODE_RECORDS = {"bvh": WIDE_BVH_NODE, "flat": BVH_NODE}
# The swizzle that reads an argument of n components from its vec4 row.
_ARGUMENT_COMPONENTS = {1: ".x", 2: ".xy", 3: ".xyz", 4: ""}


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
    variant: KernelVariant = DEFAULT_VARIANT,
    generated: dict[str, str] | None = None,
) -> np.ndarray:
    """Run `wgsl` (which defines `fn compute(i: u32) -> OUTPUT`) for i in [0, count).

    inputs[k] is bound read-only as `inputs_k: array<input_types[k]>`. `scene` fills the scene group
    by binding name (frame, triangles, nodes, materials, lights): arrays are uploaded (triangles as
    texels; nodes as the flat list's storage buffer), GPU resources (`node_binding`) bound as they
    are. `groups` adds bind groups with their resources by binding name; the kernel is compiled for
    `variant` (the features whose code the test includes), with `generated` files added.
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
    kernel = compute_kernel(
        context,
        "harness_entry.wgsl",
        (scene_group(acceleration), harness, *groups),
        variant,
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


def run_per_case(
    context, includes: Sequence[str], arguments: dict[str, np.ndarray], body: str, **options
) -> np.ndarray:
    """Run `body` (WGSL statements that return a vec4<f32>; `i` is the case's index) once per case.
    Each of `arguments` holds one value per case, (count,) or (count, n) with n <= 4, and is a `let`
    of its name in the body (f32 or vecn<f32>, read from one vec4 row of inputs_0). `includes` are
    the files the body calls, `options` run_kernel's. Returns (count, 4) float32."""
    count = len(next(iter(arguments.values())))
    rows = np.zeros((count, len(arguments), 4), np.float32)
    lines = [f'//! include "{path}"' for path in includes] + ["fn compute(i: u32) -> vec4<f32> {"]
    for k, (name, values) in enumerate(arguments.items()):
        columns = np.reshape(values, (count, -1))
        rows[:, k, : columns.shape[1]] = columns
        components = _ARGUMENT_COMPONENTS[columns.shape[1]]
        lines.append(f"    let {name} = inputs_0[{len(arguments)}u * i + {k}u]{components};")
    wgsl = "\n".join([*lines, body, "}"])
    vec4 = np.dtype((np.float32, 4))
    return run_kernel(
        context, wgsl, [rows.reshape(-1, 4)], vec4, count, input_types=["vec4<f32>"], output_type="vec4<f32>", **options
    )


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
    records as texels, the flat list's boxes as an array for a storage buffer.
    """
    if records.acceleration.kind == "bvh":
        return TrackedTexels(context, "nodes", records.nodes).resource
    return records.nodes


def read_binding(context, resource, dtype: np.dtype, count: int) -> np.ndarray:
    """The first `count` records of a bound buffer or texel texture (`TrackedTexels`)."""
    if isinstance(resource, wgpu.GPUBuffer):
        return read_buffer(context, resource, dtype, count)
    texels = read_texture(context, resource.texture, np.uint32, 4)
    # a texture of 3-texel records need not hold a whole number of them: cut before viewing
    return np.frombuffer(texels.tobytes()[: count * dtype.itemsize], dtype).copy()


def frame_record(node_count: int = 0) -> np.ndarray:
    record = FRAME.zeros(1)
    record["node_count"] = node_count
    return record


__all__ = [
    "WORKGROUP",
    "frame_record",
    "harness_group",
    "node_binding",
    "read_binding",
    "run_kernel",
    "run_per_case",
]
