// Diffuse (Lambertian) reflection: eval, sample and pdf, cosine-weighted sampling.
//! include "sampling/warps.wgsl"
//! include "materials/bsdf_sample.wgsl"

fn diffuse_eval(color: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return color * (INV_PI * wo.z);
}

fn diffuse_pdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    return select(0.0, pdf_cosine_hemisphere(wo.z), wi.z > 0.0);
}

fn diffuse_sample(color: vec3<f32>, wi: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    if wi.z <= 0.0 {
        return no_bsdf_sample();
    }
    let wo = sample_cosine_hemisphere(u);
    // eval / pdf = (color wo.z / pi) / (wo.z / pi): exactly the albedo
    return BsdfSample(wo, color, pdf_cosine_hemisphere(wo.z), false, 1.0);
}
