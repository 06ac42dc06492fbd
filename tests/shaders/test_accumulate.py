"""accumulate_sample: 100,000 heavy-tailed float32 samples per pixel summed
without drift, and non-finite samples counted instead of added."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.gpu.layout import ACCUMULATED_PIXEL
from wgputrace.testing.harness import run_kernel

pytestmark = pytest.mark.gpu

ACCUMULATE_SEED = 1_000_003
PIXELS = 64
SAMPLES_PER_PIXEL = 100_000
# Lognormal radiance with this sigma: a few samples per pixel are 10^4 times the median, like
# fireflies next to dim paths.
LOGNORMAL_SIGMA = 2.0
# Kahan summation of positive values is off by at most 2u + O(N u^2) ~ 1.2e-7 relative
# (u = 2^-24, N = 1e5); 1e-6 leaves 8x room (measured: 2e-9). A naive float32 sum drifts by ~1e-5
# (median over pixels), as test_naive_float32_sum_fails_the_same_bound shows: the bound can fail.
RELATIVE_TOLERANCE = 1e-6
# The first pixels get non-finite samples: NaN, +inf and -inf, in one channel or all three.
NON_FINITE_PIXELS = 8
NON_FINITE_PER_PIXEL = 5

# lavapipe (Mesa's llvmpipe) stops all loops after 65,535 iterations per invocation together (nested loops
# included), so each iteration takes this many consecutive samples in straight-line code.
SAMPLES_PER_ITERATION = 4
SUM_KERNEL = """
//! include "integrators/accumulate.wgsl"
fn sample_value(at: u32) -> vec3<f32> {{
    return vec3<f32>(inputs_0[3u * at], inputs_0[3u * at + 1u], inputs_0[3u * at + 2u]);
}}
fn compute(i: u32) -> {output} {{
    var pixel = AccumulatedPixel(vec4<f32>(0.0), vec4<f32>(0.0));
    for (var k = i * {samples}u; k < (i + 1u) * {samples}u; k += {unroll}u) {{
{steps}
    }}
    return {result};
}}
"""


def sum_kernel(output: str, step: str, result: str) -> str:
    """A kernel summing pixel i's samples with `step` (WGSL using `value`) into `pixel`."""
    steps = "\n".join(f"        {{ let value = sample_value(k + {n}u); {step} }}" for n in range(SAMPLES_PER_ITERATION))
    return SUM_KERNEL.format(
        output=output, samples=SAMPLES_PER_PIXEL, unroll=SAMPLES_PER_ITERATION, steps=steps, result=result
    )


KAHAN_KERNEL = sum_kernel("AccumulatedPixel", "pixel = accumulate_sample(pixel, value);", "pixel")
# The control: the same loop adding plainly in float32 (non-finite samples skipped the same way).
NAIVE_KERNEL = sum_kernel("vec4<f32>", "if is_finite_vec3(value) { pixel.sum += vec4<f32>(value, 0.0); }", "pixel.sum")


@pytest.fixture(scope="module")
def samples() -> tuple[np.ndarray, np.ndarray]:
    """(values (PIXELS, SAMPLES_PER_PIXEL, 3) float32, non_finite (PIXELS, SAMPLES_PER_PIXEL) bool)."""
    rng = np.random.default_rng(ACCUMULATE_SEED)
    values = rng.lognormal(0.0, LOGNORMAL_SIGMA, size=(PIXELS, SAMPLES_PER_PIXEL, 3)).astype(np.float32)
    non_finite = np.zeros(values.shape[:2], bool)
    for pixel in range(NON_FINITE_PIXELS):
        where = rng.choice(SAMPLES_PER_PIXEL, size=NON_FINITE_PER_PIXEL, replace=False)
        for k, bad in zip(where, rng.choice([np.nan, np.inf, -np.inf], size=NON_FINITE_PER_PIXEL), strict=True):
            channels = slice(None) if rng.random() < 0.5 else int(rng.integers(0, 3))
            values[pixel, k, channels] = bad
        non_finite[pixel, where] = True
    return values, non_finite


def run_sum(context, kernel: str, values: np.ndarray, dtype: np.dtype, output: str) -> np.ndarray:
    return run_kernel(context, kernel, [values.reshape(-1)], dtype, PIXELS, input_types=["f32"], output_type=output)


@pytest.fixture(scope="module")
def accumulated(gpu_context, samples) -> np.ndarray:
    return run_sum(gpu_context, KAHAN_KERNEL, samples[0], ACCUMULATED_PIXEL.dtype, "AccumulatedPixel")


def reference_sums(values: np.ndarray, non_finite: np.ndarray) -> np.ndarray:
    """float64 sums of the finite samples' float32 values, (PIXELS, 3)."""
    return np.where(non_finite[..., None], 0.0, values).sum(axis=1, dtype=np.float64)


def test_kahan_sum_does_not_drift(samples, accumulated):
    values, non_finite = samples
    total = accumulated["sum"][:, :3].astype(np.float64) - accumulated["compensation"][:, :3]
    reference = reference_sums(values, non_finite)
    error = np.abs(total - reference) / reference
    worst = np.unravel_index(np.argmax(error), error.shape)
    assert error[worst] <= RELATIVE_TOLERANCE, (
        f"pixel {worst[0]} channel {worst[1]}: sum {total[worst]:.9g} vs float64 {reference[worst]:.9g}, "
        f"relative error {error[worst]:.3g} > {RELATIVE_TOLERANCE}"
    )


def test_non_finite_samples_are_counted_not_added(samples, accumulated):
    _, non_finite = samples
    assert np.isfinite(accumulated["sum"]).all() and np.isfinite(accumulated["compensation"]).all()
    counted = accumulated["sum"][:, 3]
    expected = non_finite.sum(axis=1)
    assert np.array_equal(counted, expected), (
        f"non-finite counts {counted[: NON_FINITE_PIXELS + 1]}, expected {expected[: NON_FINITE_PIXELS + 1]}"
    )


def test_naive_float32_sum_fails_the_same_bound(gpu_context, samples):
    values, non_finite = samples
    naive = run_sum(gpu_context, NAIVE_KERNEL, values, np.dtype((np.float32, 4)), "vec4<f32>")
    error = np.abs(naive[:, :3].astype(np.float64) - reference_sums(values, non_finite)) / reference_sums(
        values, non_finite
    )
    assert np.median(error) > RELATIVE_TOLERANCE, (
        f"naive float32 sums drift only {np.median(error):.3g}: the bound tests nothing"
    )
