// The independent sampler: each pixel's xoshiro128** stream (rng_next_f32), continued across samples.
// The stream's state passes from one sample to the next through rng_states.
//! include "sampling/rng.wgsl"
//! include "generated/bindings/pixels.wgsl"

// The stream where the sample under way began (sampler_end_rewound).
var<private> sample_start: vec4<u32>;

fn sampler_begin(pixel: u32) {
    rng_state = rng_states[pixel];
    sample_start = rng_state;
}

fn sampler_end(pixel: u32) {
    rng_states[pixel] = rng_state;
}

// sampler_end as if the sample under way had not begun: the next sampler_begin starts it again.
fn sampler_end_rewound(pixel: u32) {
    rng_states[pixel] = sample_start;
}

// sampler_end then sampler_begin: the stream simply goes on.
fn sampler_next_sample() {
    sample_start = rng_state;
}

fn sample_1d() -> f32 {
    return rng_next_f32();
}

fn sample_2d() -> vec2<f32> {
    return rng_next_2d();
}
