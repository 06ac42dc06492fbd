"""loop_budget_spent: on llvmpipe it tells when an invocation's loops together
ran past the driver's budget of 65,535 iterations, and never before; elsewhere it is never true.
drop_cut_short_sample counts such a sample instead of adding it."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.gpu.layout import ACCUMULATED_PIXEL
from wgputrace.testing.harness import run_kernel

pytestmark = pytest.mark.gpu

SPIN_KERNEL = """
//! include "integrators/loop_budget.wgsl"
fn compute(i: u32) -> vec2<u32> {
    var spin = 0u;
    for (var k = 0u; k < inputs_0[i]; k++) {
        spin += k;
    }
    // spin is returned so that the loop is not removed; inputs_1[i] is 1, unknown to the compiler
    return vec2<u32>(select(0u, 1u, loop_budget_spent(inputs_1[i])), spin);
}
"""
# Iterations spun before asking: well inside the budget, and past it.
INSIDE = [0, 1, 1_000, 60_000]
PAST = [70_000, 200_000]
# llvmpipe runs 8 invocations in lockstep, and the budget is theirs together (a loop runs as long
# as its longest lane): each case fills 8 consecutive invocations of its own.
LOCKSTEP_LANES = 8


def test_spent_exactly_when_the_loops_ran_past_the_budget(gpu_context):
    iterations = np.repeat(np.array(INSIDE + PAST, np.uint32), LOCKSTEP_LANES)
    out = run_kernel(
        gpu_context,
        SPIN_KERNEL,
        [iterations, np.ones_like(iterations)],
        np.dtype((np.uint32, 2)),
        len(iterations),
        input_types=["u32", "u32"],
        output_type="vec2<u32>",
    )
    spent = out[:, 0].astype(bool).reshape(-1, LOCKSTEP_LANES)
    expected_past = gpu_context.loop_iteration_limit is not None
    assert not spent[: len(INSIDE)].any()
    assert np.all(spent[len(INSIDE) :] == expected_past)


DROP_KERNEL = """
//! include "integrators/accumulate.wgsl"
fn compute(i: u32) -> AccumulatedPixel {
    var pixel = AccumulatedPixel(vec4<f32>(0.0), vec4<f32>(0.0));
    pixel = accumulate_sample(pixel, vec3<f32>(1.0, 2.0, 3.0));
    pixel = drop_cut_short_sample(pixel);
    pixel = drop_cut_short_sample(pixel);
    pixel = accumulate_sample(pixel, vec3<f32>(inputs_0[i]));
    return pixel;
}
"""


def test_a_cut_short_sample_is_counted_not_added(gpu_context):
    out = run_kernel(
        gpu_context,
        DROP_KERNEL,
        [np.array([0.5], np.float32)],
        ACCUMULATED_PIXEL.dtype,
        1,
        input_types=["f32"],
        output_type="AccumulatedPixel",
    )
    np.testing.assert_array_equal(out["sum"][0], [1.5, 2.5, 3.5, 0.0])  # no non-finite sample either
    assert out["compensation"][0, 3] == 2.0  # and the count survives the next accumulate
