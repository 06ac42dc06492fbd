"""WGSL `difference_of_products`: a * b - c * d never of the wrong sign, zero for equal products,
negated when the products swap.

The watertight triangle test relies on all three: a shared edge's function must change sign with
its orientation, and a triangle whose corners coincide must give zero edge functions. A plain
`a * b - c * d` that a compiler contracts into one fma has neither property (it failed both
intersection tests on an NVIDIA H100 before this helper).
"""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.testing.harness import run_kernel

pytestmark = pytest.mark.gpu

SEED = 20_261_123
COUNT = 20_000
KERNEL = """
//! include "geometry/difference_of_products.wgsl"
fn compute(i: u32) -> f32 {
    let x = inputs_0[i];
    return difference_of_products(x.x, x.y, x.z, x.w);
}
"""


def differences(context, operands: np.ndarray) -> np.ndarray:
    return run_kernel(
        context,
        KERNEL,
        [operands.astype(np.float32)],
        np.float32,
        len(operands),
        input_types=["vec4<f32>"],
        output_type="f32",
    )


def operands(rng: np.random.Generator) -> np.ndarray:
    """Products of nearly equal size, where one rounding decides the sign: c * d is a * b with one
    factor nudged by a few ulp, or swapped so the products are equal."""
    a = rng.uniform(-2.0, 2.0, COUNT).astype(np.float32) * np.float32(10.0) ** rng.integers(-3, 4, COUNT)
    b = rng.uniform(-2.0, 2.0, COUNT).astype(np.float32)
    nudge = rng.integers(-3, 4, COUNT)
    c = np.nextafter(b, np.where(nudge > 0, np.inf, -np.inf).astype(np.float32))
    c = np.where(nudge == 0, b, c)
    d = a.copy()
    return np.stack([a, b, c, d], axis=1).astype(np.float32)


def test_sign_is_never_wrong_and_equal_products_give_zero(gpu_context):
    x = operands(np.random.default_rng(SEED))
    result = differences(gpu_context, x)
    # float32 products are exact in float64, so this is the true value's sign
    exact = x[:, 0].astype(np.float64) * x[:, 1] - x[:, 2].astype(np.float64) * x[:, 3]
    # A fused fma gives the exact sign; an unfused one may round a tiny difference to zero.
    wrong = np.flatnonzero((np.sign(result) != np.sign(exact)) & ((result != 0) | (exact == 0)))
    assert wrong.size == 0, (
        f"{wrong.size} of {len(x)} signs wrong; first: a, b, c, d = {x[wrong[0]].tolist()}, "
        f"got {result[wrong[0]]!r}, exact {exact[wrong[0]]!r}"
    )
    assert np.any(exact == 0) and np.any(exact != 0)


def test_swapped_products_give_the_opposite_sign(gpu_context):
    x = operands(np.random.default_rng(SEED + 1))
    forward = differences(gpu_context, x)
    backward = differences(gpu_context, x[:, [2, 3, 0, 1]])
    assert np.array_equal(np.sign(forward), -np.sign(backward))
