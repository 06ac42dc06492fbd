// The independent sampler: each pixel's xoshiro128** stream (rng_next_f32), continued across samples.
// The stream's state passes from one sample to the next through rng_states.
//! include "sampling/rng.wgsl"
//! include "generated/bindings/pixels.wgsl"

fn sampler_begin(pixel: u32) {
    rng_state = rng_states[pixel];
}

fn sampler_end(pixel: u32) {
    rng_states[pixel] = rng_state;
}

// sampler_end then sampler_begin: the stream simply goes on.
fn sampler_next_sample() {}

fn sample_1d() -> f32 {
    return rng_next_f32();
}

fn sample_2d() -> vec2<f32> {
    return rng_next_2d();
}
