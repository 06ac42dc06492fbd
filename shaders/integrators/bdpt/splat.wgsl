// splat: light tracing's contributions to other pixels, summed with integer atomics in fixed point.
// 64-bit sums are the same whatever order the invocations add in (same seed, same image).
//! include "common/finite.wgsl"
//
// `splats` (pixels_group) holds SPLAT_WORDS words per pixel: for each colour channel a 64-bit
// unsigned sum of round(value x SPLAT_SCALE) as low and high words, then a count of splats dropped
// for being non-finite or too large. The resolution is 2^-24 (6e-8) per splat, rounded to nearest;
// a pixel's sum holds up to 2^40 (1.1e12) over all its samples, so one splat is refused at
// SPLAT_MAX, far beyond any radiance the test scenes reach. The renderer adds the sums to the
// camera's (Renderer) and divides both by the samples per pixel.
const SPLAT_WORDS: u32 = 8u;
const SPLAT_SCALE: f32 = 16777216.0;
const SPLAT_MAX: f32 = 1e9;
const TWO_POW_32: f32 = 4294967296.0;

fn splat_channel(word: u32, value: f32) {
    let scaled = round(value * SPLAT_SCALE);
    // both exact: scaled has 24 significant bits, and below 2^32 high is 0
    let high = floor(scaled / TWO_POW_32);
    let low = u32(scaled - high * TWO_POW_32);
    let before = atomicAdd(&splats[word], low);
    let carry = select(0u, 1u, before > 0xFFFFFFFFu - low);
    let high_add = u32(high) + carry;
    if high_add != 0u {
        atomicAdd(&splats[word + 1u], high_add);
    }
}

fn splat(pixel: u32, value: vec3<f32>) {
    let base = pixel * SPLAT_WORDS;
    if !is_finite_vec3(value) || max(value.x, max(value.y, value.z)) > SPLAT_MAX {
        atomicAdd(&splats[base + 6u], 1u);
        return;
    }
    let positive = max(value, vec3<f32>(0.0));
    splat_channel(base, positive.x);
    splat_channel(base + 2u, positive.y);
    splat_channel(base + 4u, positive.z);
}
