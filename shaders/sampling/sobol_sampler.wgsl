// The Owen-scrambled Sobol sampler: a pixel's samples are the points of its own scramble, in order.
// rng_states[pixel] holds the pixel's seed (x) and how many samples it has taken (y), so
// the sequence continues across dispatches and render calls; the renderer writes the seeds
// (pixel_sobol_states). Each draw of a sample (sample_1d or sample_2d) is the next
// dimension: its own shuffle and scramble, seeded by the pixel's seed and the draw's number.
//! include "sampling/rng.wgsl"
//! include "sampling/sobol_points.wgsl"
//! include "generated/bindings/pixels.wgsl"

var<private> sobol_pixel_seed: u32;
var<private> sobol_index: u32;
var<private> sobol_dimension: u32;

// Sample sobol_index starts at its first draw. Stochastic alpha draws independent numbers, a
// stream per pixel and sample (xoshiro's state must not be all zero: w is odd).
fn sobol_start_sample() {
    sobol_dimension = 0u;
    let stream = sobol_seed(sobol_pixel_seed, ~sobol_index);
    rng_state = vec4<u32>(stream, sobol_hash(stream + 1u), sobol_hash(stream + 2u), sobol_hash(stream + 3u) | 1u);
}

fn sampler_begin(pixel: u32) {
    let state = rng_states[pixel];
    sobol_pixel_seed = state.x;
    sobol_index = state.y;
    sobol_start_sample();
}

fn sampler_end(pixel: u32) {
    rng_states[pixel].y = sobol_index + 1u;
}

// sampler_end as if the sample under way had not begun: the next sampler_begin starts it again.
fn sampler_end_rewound(pixel: u32) {
    rng_states[pixel].y = sobol_index;
}

// sampler_end then sampler_begin, without the round trip through rng_states.
fn sampler_next_sample() {
    sobol_index++;
    sobol_start_sample();
}

// The seed of the next draw of this sample, whose number it takes.
fn sobol_next_draw_seed() -> u32 {
    let seed = sobol_seed(sobol_pixel_seed, sobol_dimension);
    sobol_dimension++;
    return seed;
}

fn sample_1d() -> f32 {
    return sobol_unit(sobol_point_1d(sobol_index, sobol_next_draw_seed()));
}

fn sample_2d() -> vec2<f32> {
    let point = sobol_point_2d(sobol_index, sobol_next_draw_seed());
    return vec2<f32>(sobol_unit(point.x), sobol_unit(point.y));
}
