// The sampler interface: sample_1d and sample_2d between sampler_begin(pixel) and sampler_end(pixel).
// sampler_next_sample() between a pixel's samples within one invocation is sampler_end then
// sampler_begin without the trip through memory (path regeneration takes several per dispatch);
// sampler_end_rewound(pixel) ends as if the sample under way had not begun.
//
// A path draws, in order: the camera's 2D point, then per vertex the light sample's 2D + 2D, the
// BSDF's 2D + 1D and roulette's 1D (where the restir integrator's first vertex resamples, it draws
// 2D + 2D + 1D per light candidate instead of one light sample, and with shared reservoirs a 2D and a
// 1D per neighbour). Estimators draw only through this interface, so a sampler
// that stratifies by dimension can stand behind it. The renderer chooses which (sampler_hook: the
// independent or the Sobol sampler), each keeping its per-pixel state in rng_states. Stochastic
// alpha (surface_blocks) draws from rng_next_f32 directly: how many times a ray meets a blended
// surface varies from path to path, so its draws cannot own dimensions.
//! include "generated/sampler.wgsl"
