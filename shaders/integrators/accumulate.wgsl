// Adding one sample to a pixel's running sum without drift, and keeping non-finite samples out.
//! include "generated/structs.wgsl"
//! include "common/constants.wgsl"
//! include "common/finite.wgsl"
//
// A float32 sum of 100,000 samples loses about five digits to rounding; Kahan's compensation
// carries the lost low-order bits so the error stays near one rounding whatever the count.
// A NaN or infinite sample adds nothing (it counts as zero radiance) and is counted in sum.w;
// compensation.w counts samples dropped for another reason (drop_cut_short_sample).

fn accumulate_sample(pixel: AccumulatedPixel, value: vec3<f32>) -> AccumulatedPixel {
    if !is_finite_vec3(value) {
        return AccumulatedPixel(pixel.sum + vec4<f32>(0.0, 0.0, 0.0, 1.0), pixel.compensation);
    }
    let y = value - pixel.compensation.xyz;
    // Compilers may treat float arithmetic as reassociable: Mesa (lavapipe) folds (t - sum) - y
    // with t = sum + y to 0, silently turning this into a plain float32 sum. max with -FLOAT_MAX
    // leaves every finite t as it is but hides from the optimiser that t is sum + y.
    let t = max(pixel.sum.xyz + y, vec3<f32>(-FLOAT_MAX));
    let lost = (t - pixel.sum.xyz) - y;
    return AccumulatedPixel(vec4<f32>(t, pixel.sum.w), vec4<f32>(lost, pixel.compensation.w));
}

// A sample whose loops the driver may have cut short (loop_budget_spent) adds nothing (it counts as
// zero radiance, like a non-finite one) and is counted in compensation.w.
fn drop_cut_short_sample(pixel: AccumulatedPixel) -> AccumulatedPixel {
    return drop_cut_short_samples(pixel, 1u);
}

// `count` such samples at once (no loop: where they are dropped, the driver ends every loop).
fn drop_cut_short_samples(pixel: AccumulatedPixel, count: u32) -> AccumulatedPixel {
    return AccumulatedPixel(pixel.sum, pixel.compensation + vec4<f32>(0.0, 0.0, 0.0, f32(count)));
}
