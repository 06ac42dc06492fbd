// The numbers a path draws, in the order it draws them: the camera's 2D point, then per vertex
// the light sample's 2D + 2D, the BSDF's 2D + 1D and roulette's 1D. Estimators draw only through
// sample_1d and sample_2d, so a sampler that stratifies by dimension can stand behind them.
// Stochastic alpha (alpha.wgsl) draws from rng_next_f32 directly: how many times a ray meets a
// blended surface varies from path to path, so its draws cannot own dimensions.
//! include "rng.wgsl"
//! include "generated/bindings/pixels.wgsl"

fn sampler_begin(pixel: u32) {
    rng_state = rng_states[pixel];
}

fn sampler_end(pixel: u32) {
    rng_states[pixel] = rng_state;
}

fn sample_1d() -> f32 {
    return rng_next_f32();
}

fn sample_2d() -> vec2<f32> {
    return rng_next_2d();
}
