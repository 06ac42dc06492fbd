"""Bind groups declared once: the generated WGSL and the layouts agree with the declarations, no
shipped shader declares a binding or a workgroup size by hand, bind groups made by one kernel
work on another, and a mis-named resource is refused by name."""

from __future__ import annotations

import re

import numpy as np
import pytest

from wgputrace.gpu.bindings import IMAGE_WORKGROUP, STORAGE_READ_WRITE, BindGroup, Binding
from wgputrace.gpu.buffers import read_buffer, storage_buffer
from wgputrace.gpu.kernel import ComputeKernel
from wgputrace.gpu.shader_source import shader_root
from wgputrace.kernels.bind_groups import BAND_GROUP, PIXELS_GROUP, RAY_COUNT_GROUP, scene_group
from wgputrace.testing.harness import harness_group
from wgputrace.view.layout import ATROUS_GROUP, BOX_LINES_GROUP, GUIDES_GROUP, PRESENT_GROUP, RESOLVE_GROUP

GROUPS = [
    scene_group("bvh"),
    scene_group("flat"),
    PIXELS_GROUP,
    BAND_GROUP,
    RAY_COUNT_GROUP,
    GUIDES_GROUP,
    RESOLVE_GROUP,
    ATROUS_GROUP,
    PRESENT_GROUP,
    BOX_LINES_GROUP,
    harness_group(["f32", "vec4<u32>"], "u32"),
]
_DECLARATION = re.compile(r"^@group\((\d+)\) @binding\((\d+)\) var(?:<[^>]*>)? (\w+): ")


@pytest.mark.parametrize("group", GROUPS, ids=lambda g: f"{g.name}-{g.index}")
def test_generated_declarations_follow_the_declaration(group: BindGroup):
    lines = [line for line in group.wgsl().splitlines() if not line.startswith("//")]
    parsed = [_DECLARATION.match(line).groups() for line in lines]
    expected = [(str(group.index), str(slot), b.name) for slot, b in enumerate(group.bindings)]
    assert parsed == expected
    entries = [b.layout_entry(slot, group.visibility) for slot, b in enumerate(group.bindings)]
    assert [entry["binding"] for entry in entries] == list(range(len(group.bindings)))


def test_the_acceleration_variant_changes_only_the_nodes():
    bvh, flat = scene_group("bvh"), scene_group("flat")
    assert [b.name for b in bvh.bindings] == [b.name for b in flat.bindings]
    differing = [a.name for a, b in zip(bvh.bindings, flat.bindings, strict=True) if a != b]
    assert differing == ["nodes"]
    with pytest.raises(ValueError, match="acceleration"):
        scene_group("octree")


def test_no_shipped_shader_declares_a_binding_or_a_workgroup_by_hand():
    for path in sorted(shader_root().rglob("*.wgsl")):
        text = path.read_text()
        assert "@group(" not in text, f"{path.name}: bindings belong in BindGroup declarations"
        sizes = re.findall(r"@workgroup_size\(([^)]*)\)", text)
        assert all(not re.search(r"\d", size) for size in sizes), f"{path.name}: @workgroup_size({sizes})"


def _counter_group(name: str) -> BindGroup:
    return BindGroup(name, 0, (Binding("counts", STORAGE_READ_WRITE, "u32"),))


def _kernel(context, body: str, group: BindGroup, workgroup: tuple[int, int] = IMAGE_WORKGROUP) -> ComputeKernel:
    entry = "\n".join(
        [
            f'//! include "{group.file}"',
            '//! include "generated/workgroup.wgsl"',
            "@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)",
            "fn main(@builtin(global_invocation_id) id: vec3<u32>) {",
            f"    {body}",
            "}",
        ]
    )
    return ComputeKernel(context, "entry.wgsl", (group,), workgroup_size=workgroup, generated={"entry.wgsl": entry})


@pytest.mark.gpu
def test_a_bind_group_made_by_one_kernel_works_on_another(gpu_context):
    group = _counter_group("shared_counts")
    first = _kernel(gpu_context, "if id.x < 4u && id.y == 0u { counts[id.x] += 1u; }", group)
    second = _kernel(gpu_context, "if id.x < 4u && id.y == 0u { counts[id.x] += 10u * (id.x + 1u); }", group)
    counts = storage_buffer(gpu_context, "counts", np.zeros(4, np.uint32), read_back=True)
    bound = {"shared_counts": first.bind("shared_counts", counts=counts)}
    first.dispatch((4, 1), bound)
    second.dispatch((4, 1), bound)
    np.testing.assert_array_equal(read_buffer(gpu_context, counts, np.uint32, 4), [11, 21, 31, 41])


@pytest.mark.gpu
def test_dispatch_covers_the_size_with_the_declared_workgroup(gpu_context):
    group = _counter_group("pixel_counts")
    width, height = 7, 11
    body = f"if id.x < {width}u && id.y < {height}u {{ counts[id.y * {width}u + id.x] += 1u; }}"
    kernel = _kernel(gpu_context, body, group, workgroup=(3, 5))
    assert kernel.workgroups((width, height)) == (3, 3, 1)
    counts = storage_buffer(gpu_context, "counts", np.zeros(width * height, np.uint32), read_back=True)
    kernel.dispatch((width, height), {"pixel_counts": kernel.bind("pixel_counts", counts=counts)}, repeat=2)
    np.testing.assert_array_equal(read_buffer(gpu_context, counts, np.uint32, width * height), 2)


@pytest.mark.gpu
def test_a_misnamed_resource_is_refused_by_name(gpu_context):
    kernel = _kernel(gpu_context, "counts[0] = 1u;", _counter_group("named_counts"))
    counts = storage_buffer(gpu_context, "counts", np.zeros(1, np.uint32))
    with pytest.raises(KeyError, match=r"no resource for counts; no binding named count\b"):
        kernel.bind("named_counts", count=counts)
    with pytest.raises(KeyError, match="declares no bind group 'scene'"):
        kernel.bind("scene", counts=counts)
    with pytest.raises(KeyError, match="needs bind groups named_counts"):
        kernel.dispatch((1, 1), {})


@pytest.mark.gpu
def test_groups_sharing_an_index_are_refused(gpu_context):
    with pytest.raises(ValueError, match="'pixels' and 'guides' share index 1"):
        ComputeKernel(gpu_context, "view/first_hit_guides.wgsl", (scene_group("bvh"), PIXELS_GROUP, GUIDES_GROUP))
