// A constant environment: the same radiance from every direction, sampled uniformly over the sphere.
//! include "lights/environment.wgsl"
//! include "sampling/warps.wgsl"
//
// Uniform over the whole sphere, not cosine-weighted about the receiver's normal: its density does
// not depend on the receiving point, so a ray escaping the scene can be weighted by it alone.

fn environment_radiance(direction: vec3<f32>) -> vec3<f32> {
    return lighting.environment_radiance;
}

fn environment_sample(u: vec2<f32>) -> vec3<f32> {
    return sample_uniform_sphere(u);
}

fn environment_pdf(direction: vec3<f32>) -> f32 {
    return pdf_uniform_sphere();
}
