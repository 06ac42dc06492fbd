// Directional lights: one direction everywhere, the irradiance of a surface facing it.
//! include "lights/direct_light_sample.wgsl"
//! include "lights/light_path_sample.wgsl"

// `direction` is the way the light travels; the sample looks the other way, to infinity.
fn directional_light_sample(light: LightSource, p: vec3<f32>) -> LightSample {
    return LightSample(p, light.direction, light.emission, 0u, 1.0, -light.direction, true, true);
}

// Light paths from a directional light: its one direction, from anywhere on the scene's disc.
fn directional_emission_sample(light: LightSource, disk: SceneDisk, u: vec2<f32>) -> EmissionSample {
    return distant_emission_sample(disk, u, light.direction, light.emission, 1.0, true);
}
