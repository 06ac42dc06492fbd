// Directional lights: one direction everywhere, the irradiance of a surface facing it.
//! include "light_sample.wgsl"

// `direction` is the way the light travels; the sample looks the other way, to infinity.
fn directional_light_sample(light: LightSource, p: vec3<f32>) -> LightSample {
    return LightSample(p, light.direction, light.emission, 0u, 1.0, -light.direction, true, true);
}
