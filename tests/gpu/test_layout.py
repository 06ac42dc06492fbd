"""Struct layouts: numpy dtypes agree with WGSL's layout rules, checked on the GPU by an echo kernel
that reads every field of a record, changes it, and writes it back."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.gpu.layout import ALL_STRUCTS, GpuStruct
from wgputrace.testing.harness import run_kernel

RECORDS = 37


def echo_wgsl(struct: GpuStruct) -> str:
    """compute(i) copies record i field by field, adding 1 to every component: a field read from
    or written to the wrong offset shows up as a mismatch (a whole-struct copy would hide it)."""
    lines = [
        '//! include "generated/structs.wgsl"',
        f"fn compute(i: u32) -> {struct.name} {{",
        "    var r = inputs_0[i];",
    ]
    for name, wgsl_type in struct.fields:
        one = "1u" if "u32" in wgsl_type else ("1i" if "i32" in wgsl_type else "1.0")
        lines.append(f"    r.{name} = inputs_0[i].{name} + {one};")
    lines += ["    return r;", "}"]
    return "\n".join(lines)


def random_records(struct: GpuStruct, rng) -> np.ndarray:
    records = struct.zeros(RECORDS)
    for name, _ in struct.fields:
        field = records[name]
        if field.dtype.kind == "f":
            records[name] = rng.uniform(-100, 100, field.shape).astype(np.float32)
        else:
            records[name] = rng.integers(0, 2**31, field.shape)
    return records


@pytest.mark.parametrize("struct", ALL_STRUCTS, ids=lambda s: s.name)
def test_struct_round_trips_through_echo_kernel(gpu_context, rng, struct):
    records = random_records(struct, rng)
    out = run_kernel(
        gpu_context,
        echo_wgsl(struct),
        [records],
        struct.dtype,
        RECORDS,
        input_types=[struct.name],
        output_type=struct.name,
    )
    for name, _ in struct.fields:
        np.testing.assert_array_equal(out[name], records[name] + 1, err_msg=f"{struct.name}.{name}")


def test_layout_rules_match_wgsl_spec():
    """vec3 aligns to 16 but is 12 long, so a scalar packs behind it; struct size rounds up to the
    largest alignment (the WGSL spec's worked examples)."""
    s = GpuStruct("S", (("a", "vec3<f32>"), ("b", "u32"), ("c", "vec2<f32>"), ("d", "vec3<f32>")))
    assert s.offsets == (0, 12, 16, 32)
    assert s.size == 48
    assert s.dtype.itemsize == 48
    t = GpuStruct("T", (("a", "f32"), ("b", "vec4<f32>")))
    assert t.offsets == (0, 16) and t.size == 32


def test_compact_records():
    """Bytes per record that the GPU memory budget depends on."""
    sizes = {s.name: s.size for s in ALL_STRUCTS}
    assert sizes["Triangle"] == 48
    assert sizes["BvhNode"] == 32
    assert sizes["WideBvhNode"] == 112  # 7 texels: four boxes by axis, four child words
    assert (
        sizes["Material"] == 64
    )  # 60 bytes of fields (absorption, clearcoat, sheen), 16-byte aligned: per material, not per triangle
