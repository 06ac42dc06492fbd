"""Records kept as texels (`TrackedTexels`, `texel_loader`): the generated WGSL loader reassembles every field of
every struct bit for bit, at indices spread over many texture rows; changed rows are written and
nothing else; a first allocation has no spare capacity, growth past it reallocates with spare."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.gpu import texels as texels_module
from wgputrace.gpu.layout import BVH_NODE, MATERIAL, TRIANGLE, GpuStruct
from wgputrace.gpu.texels import MAX_TEXEL_ROW, TEXEL_BYTES, TrackedTexels, texel_loader, texture_shape
from wgputrace.gpu.tracked_buffer import SPARE_FRACTION
from wgputrace.testing.harness import read_binding, run_kernel

pytestmark = pytest.mark.gpu

# Enough records for a texture of dozens of rows, so that the column mask and the row shift both
# matter (and 3-texel triangles straddle rows).
RECORDS = 3_000

LOADER_KERNEL = """
//! include "generated/structs.wgsl"
//! include "common/texels.wgsl"
//! include "generated/bindings/scene.wgsl"
{loader}
fn compute(i: u32) -> {name} {{
    return load_{name}(nodes, inputs_0[i]);
}}
"""


def random_records(rng, struct: GpuStruct, count: int) -> np.ndarray:
    """Records whose every byte is random, padding included (the texture holds padding too)."""
    raw = rng.integers(0, 2**32, size=count * struct.size // 4, dtype=np.uint64).astype(np.uint32)
    # finite floats only: a NaN's payload need not survive a bitcast round trip through f32 registers
    floats = raw.view(np.float32)
    floats[~np.isfinite(floats)] = 1.5
    return raw.view(struct.dtype).copy()


@pytest.mark.parametrize("struct", [BVH_NODE, TRIANGLE, MATERIAL], ids=lambda s: s.name)
def test_generated_loader_reassembles_every_field(gpu_context, rng, struct):
    data = random_records(rng, struct, RECORDS)
    texels = TrackedTexels(gpu_context, "records", data)
    assert texels.texture.size[1] > 1
    order = rng.permutation(RECORDS).astype(np.uint32)  # random access, as traversal does
    loaded = run_kernel(
        gpu_context,
        LOADER_KERNEL.format(loader=texel_loader(struct), name=struct.name),
        [order],
        struct.dtype,
        RECORDS,
        input_types=["u32"],
        output_type=struct.name,
        scene={"nodes": texels.resource},
    )
    for name in struct.dtype.names:
        np.testing.assert_array_equal(loaded[name], data[order][name], err_msg=f"{struct.name}.{name}")


@pytest.mark.parametrize("texel_count", [1, 2, 3, 31, 1024, 1025, 10_000, 2_500_000, 60_000_000])
def test_texture_shape_is_a_power_of_two_wide_and_wastes_under_one_row(texel_count):
    width, height = texture_shape(texel_count)
    assert width & (width - 1) == 0 and width <= MAX_TEXEL_ROW
    assert width * height >= texel_count > width * (height - 1)
    assert width <= height or width == MAX_TEXEL_ROW


def test_upload_writes_only_changed_rows_and_the_texture_equals_the_host(gpu_context, rng):
    data = random_records(rng, BVH_NODE, RECORDS)
    texels = TrackedTexels(gpu_context, "nodes", data)
    # no spare before the records grow, and less than one texture row unused
    unused_texels = texels.capacity_bytes // TEXEL_BYTES - RECORDS * texels.texels_per_record
    assert 0 <= unused_texels < texels.texture.size[0]
    # runs that start mid-row, end mid-row, cover whole rows, and a single row at the very end
    width_records = texels.texture.size[0] // texels.texels_per_record
    rows = np.unique(np.concatenate([np.arange(5, 5 + 3 * width_records), [100], [RECORDS - 1]]))
    changed = data.copy()
    changed[rows] = random_records(rng, BVH_NODE, len(rows))
    texels.uploads.bytes = texels.uploads.calls = 0
    texels.upload(changed, rows)
    assert texels.uploads.bytes == len(rows) * BVH_NODE.size
    assert texels.uploads.calls <= 3 * 3  # three runs, each at most three rectangles
    assert texels.generation == 1
    np.testing.assert_array_equal(read_binding(gpu_context, texels.resource, BVH_NODE.dtype, RECORDS), changed)


def test_growth_past_the_capacity_reallocates_with_everything(gpu_context, rng):
    data = random_records(rng, BVH_NODE, 100)
    texels = TrackedTexels(gpu_context, "nodes", data)
    grown = random_records(rng, BVH_NODE, texels.capacity_records + 1)
    texels.upload(grown, np.arange(100, len(grown)))
    assert texels.generation == 2 and texels.capacity_records >= len(grown) * (1 + SPARE_FRACTION)
    np.testing.assert_array_equal(read_binding(gpu_context, texels.resource, BVH_NODE.dtype, len(grown)), grown)


def test_growth_near_the_texture_size_limit_keeps_only_the_spare_that_fits(gpu_context, rng, monkeypatch):
    # rows of 4 texels, at most 30 of them: 60 two-texel nodes fit, 50 grown by the usual spare would not
    monkeypatch.setattr(texels_module, "MAX_TEXEL_ROW", 4)
    monkeypatch.setitem(gpu_context.device.limits, "max-texture-dimension-2d", 30)
    texels = TrackedTexels(gpu_context, "nodes", random_records(rng, BVH_NODE, 16))
    grown = random_records(rng, BVH_NODE, 50)
    texels.upload(grown)
    assert texels.capacity_records == 60 and texels.texture.size[1] == 30
    np.testing.assert_array_equal(read_binding(gpu_context, texels.resource, BVH_NODE.dtype, len(grown)), grown)


def test_records_that_do_not_fill_whole_texels_are_refused(gpu_context):
    with pytest.raises(ValueError, match="do not fill whole 16-byte texels"):
        TrackedTexels(gpu_context, "odd", np.zeros(4, np.dtype([("a", "<u4"), ("b", "<u4"), ("c", "<u4")])))
