// Point lights: the one direction towards the light, its intensity over the squared distance.
//! include "lights/direct_light_sample.wgsl"
//! include "lights/light_path_sample.wgsl"

// A point light seen from `p`: a delta, so its density is 1 (times the selection probability the
// dispatch applies). At p itself the direction is NaN, which direct lighting refuses.
fn point_light_sample(light: LightSource, p: vec3<f32>) -> LightSample {
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    let from_light = -to_light * inverseSqrt(distance_squared);
    return LightSample(light.position, from_light, light.emission / distance_squared, 0u, 1.0, vec3<f32>(0.0), false, true);
}

// Light paths from a point light: every direction alike.
fn point_emission_sample(light: LightSource, u: vec2<f32>) -> EmissionSample {
    let direction = sample_uniform_sphere(u);
    let pdf = point_emission_pdf(light, direction);
    return EmissionSample(light.position, direction, direction, light.emission, pdf.position, pdf.direction, 0u, true, false, false);
}

fn point_emission_pdf(light: LightSource, direction: vec3<f32>) -> EmissionPdf {
    return EmissionPdf(1.0, pdf_uniform_sphere());
}
