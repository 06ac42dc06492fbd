// Point lights: the one direction towards the light, its intensity over the squared distance.
//! include "light_sample.wgsl"

// A point light seen from `p`: a delta, so its density is 1 (times the selection probability the
// dispatch applies). At p itself the direction is NaN, which direct lighting refuses.
fn point_light_sample(light: LightSource, p: vec3<f32>) -> LightSample {
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    let from_light = -to_light * inverseSqrt(distance_squared);
    return LightSample(light.position, from_light, light.emission / distance_squared, 0u, 1.0, vec3<f32>(0.0), false, true);
}
