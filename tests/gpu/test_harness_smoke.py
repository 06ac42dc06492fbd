import numpy as np

from wgputrace.testing.harness import run_kernel


def test_harness_runs_shipped_code(gpu_context):
    x = np.linspace(-3, 3, 100, dtype=np.float32)
    wgsl = '//! include "common/finite.wgsl"\nfn compute(i: u32) -> f32 { return inputs_0[i] * 2.0; }'
    out = run_kernel(gpu_context, wgsl, [x], np.float32, 100, input_types=["f32"], output_type="f32")
    np.testing.assert_array_equal(out, 2 * x)
