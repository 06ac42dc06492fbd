// The environment as a light: what every environment variant (constant, map) shares.
//! include "lights/direct_light_sample.wgsl"
//! include "lights/light_path_sample.wgsl"
//
// Each variant defines, beside each other: environment_radiance(direction), the radiance arriving
// from `direction` (towards the sky, world space); environment_sample(u), a direction; and
// environment_pdf(direction), the density per steradian with which environment_sample draws it.

fn environment_light_sample(p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let direction = environment_sample(u);
    return LightSample(p, -direction, environment_radiance(direction), 0u, environment_pdf(direction), direction, true, false);
}

// Light paths from the environment: a direction as environment_sample draws it, from the scene's disc.
fn environment_emission_sample(disk: SceneDisk, u_position: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    let towards = environment_sample(u_direction);
    return distant_emission_sample(disk, u_position, -towards, environment_radiance(towards), environment_pdf(towards), false);
}
