// Principled's anisotropy: Mitsuba 3's `anisotropic`, GGX of alpha_u along the surface tangent (the
// shading frame's x: `surface_frame`) and alpha_v along the bitangent, for its reflection and
// transmission alike.
//
// Mitsuba's calc_dist_params: aspect = sqrt(1 - 0.9 anisotropic), alpha_u = max(0.001, roughness^2 /
// aspect), alpha_v = max(0.001, roughness^2 aspect). D, Smith's G1 and the visible-normal sampling
// are glossy.wgsl's with alpha per axis (Heitz 2018 stretches wi by the two alphas); they are not
// written over glossy.wgsl's isotropic ones because those must stay as they are for the images of
// scenes without anisotropy, which compile the isotropic stubs of generated/principled_lobes.wgsl.
//! include "materials/principled_parameters.wgsl"
//! include "materials/glossy.wgsl"

// the most anisotropic Mitsuba's aspect gets: alpha_u / alpha_v = 1 / (1 - 0.9) at anisotropic 1
const ANISOTROPIC_ASPECT_RANGE: f32 = 0.9;

// (alpha_u, alpha_v)
fn principled_alphas(p: Principled) -> vec2<f32> {
    let aspect = sqrt(1.0 - ANISOTROPIC_ASPECT_RANGE * p.anisotropic);
    let roughness2 = p.roughness * p.roughness;
    return max(vec2<f32>(PRINCIPLED_ALPHA_MIN), vec2<f32>(roughness2 / aspect, roughness2 * aspect));
}

// D(m) of anisotropic GGX, for m in the upper hemisphere
fn principled_ggx_d(p: Principled, m: vec3<f32>) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let alpha = principled_alphas(p);
    let s = (m.x / alpha.x) * (m.x / alpha.x) + (m.y / alpha.y) * (m.y / alpha.y) + m.z * m.z;
    return 1.0 / (PI * alpha.x * alpha.y * s * s);
}

// Smith's G1(v, m); zero where v sees the back of the microfacet
fn principled_ggx_g1(p: Principled, v: vec3<f32>, m: vec3<f32>) -> f32 {
    if dot(v, m) * v.z <= 0.0 {
        return 0.0;
    }
    let alpha = principled_alphas(p);
    let tan2_alpha2 = ((alpha.x * v.x) * (alpha.x * v.x) + (alpha.y * v.y) * (alpha.y * v.y)) / (v.z * v.z);
    return 2.0 / (1.0 + sqrt(1.0 + tan2_alpha2));
}

// A normal from D_wi(m) = G1(wi, m) max(0, wi.m) D(m) / wi.z: wi stretched to the isotropic
// configuration of alpha 1, its visible normal drawn there (sample_ggx_visible_normal), unstretched.
fn principled_ggx_visible_normal(p: Principled, wi: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let alpha = principled_alphas(p);
    let stretched = sample_ggx_visible_normal(normalize(vec3<f32>(alpha.x * wi.x, alpha.y * wi.y, wi.z)), 1.0, u);
    return normalize(vec3<f32>(alpha.x * stretched.x, alpha.y * stretched.y, max(0.0, stretched.z)));
}

// The density of wo = reflect(-wi, m) for m from principled_ggx_visible_normal (pdf_ggx_reflection's)
fn principled_ggx_reflection_pdf(p: Principled, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    return principled_ggx_g1(p, wi, m) * principled_ggx_d(p, m) / (4.0 * wi.z);
}
