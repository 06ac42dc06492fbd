// The environment as a light: what every environment variant shares (environment_constant.wgsl, environment_map.wgsl).
//! include "light_sample.wgsl"
//
// Each variant defines, beside each other: environment_radiance(direction), the radiance arriving
// from `direction` (towards the sky, world space); environment_sample(u), a direction; and
// environment_pdf(direction), the density per steradian with which environment_sample draws it.

fn environment_light_sample(p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let direction = environment_sample(u);
    return LightSample(p, -direction, environment_radiance(direction), 0u, environment_pdf(direction), direction, true, false);
}
