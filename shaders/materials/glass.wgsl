// Glass: a smooth dielectric, exact Fresnel choosing between mirror reflection and refraction.
// Total internal reflection falls out of it. Both lobes are deltas, so eval and pdf are zero.
//! include "materials/bsdf_sample.wgsl"

struct Fresnel {
    reflectance: f32,
    // cosine of the refracted direction, on the side opposite the incident one
    cos_theta_t: f32,
    // relative ior eta_incident / eta_transmitted, which scales the tangential component
    eta_ti: f32,
}

// Unpolarized Fresnel reflectance at a boundary with ior `eta` inside (the -z side) and 1 outside.
fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> Fresnel {
    let outside = cos_theta_i >= 0.0;
    let eta_it = select(1.0 / eta, eta, outside);
    let eta_ti = 1.0 / eta_it;
    let cos_t2 = 1.0 - eta_ti * eta_ti * (1.0 - cos_theta_i * cos_theta_i);
    if cos_t2 <= 0.0 {
        return Fresnel(1.0, 0.0, eta_ti);
    }
    let cos_i = abs(cos_theta_i);
    let cos_t = sqrt(cos_t2);
    let a_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
    let a_p = (cos_t - eta_it * cos_i) / (cos_t + eta_it * cos_i);
    return Fresnel(0.5 * (a_s * a_s + a_p * a_p), select(cos_t, -cos_t, outside), eta_ti);
}

fn glass_eval(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn glass_pdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    return 0.0;
}

fn glass_sample(color: vec3<f32>, ior: f32, wi: vec3<f32>, u: f32) -> BsdfSample {
    let fresnel = fresnel_dielectric(wi.z, ior);
    if u < fresnel.reflectance {
        return BsdfSample(vec3<f32>(-wi.x, -wi.y, wi.z), vec3<f32>(1.0), fresnel.reflectance, true, 1.0);
    }
    let wo = vec3<f32>(-fresnel.eta_ti * wi.x, -fresnel.eta_ti * wi.y, fresnel.cos_theta_t);
    // radiance is compressed into a smaller solid angle on entering a denser medium: scale by eta_ti^2
    let weight = color * (fresnel.eta_ti * fresnel.eta_ti);
    return BsdfSample(wo, weight, 1.0 - fresnel.reflectance, true, fresnel.eta_ti);
}
