// Principled's clearcoat: Mitsuba 3's transcription of Burley's second specular lobe, from outside.
//
// A GTR1 microfacet distribution of alpha lerp(0.1, 0.001, clearcoat_gloss), Schlick's Fresnel about
// a normal reflectance of 0.04 (eta 1.5; the refracted angle where the material's eta is below 1, as
// Mitsuba's calc_schlick), and a separable Smith G of fixed alpha 0.25, weighted 0.25 clearcoat:
// f cos_o = 0.25 clearcoat F D G cos_o. Like Mitsuba's, without the 1 / (4 cos_i cos_o) of a
// microfacet BRDF. Sampled (at Mitsuba's rate 0.25 clearcoat) by a GTR1 normal, not a visible one.
// Compiled only into kernels of scenes that use it (generated/principled_lobes.wgsl).
//! include "common/constants.wgsl"
//! include "materials/principled_parameters.wgsl"

// Burley's clearcoat weight, and its Fresnel reflectance at normal incidence (eta 1.5)
const CLEARCOAT_WEIGHT: f32 = 0.25;
const CLEARCOAT_R0: f32 = 0.04;
// GTR1 alpha at clearcoat_gloss 0 and 1
const CLEARCOAT_ALPHA_ROUGH: f32 = 0.1;
const CLEARCOAT_ALPHA_GLOSSY: f32 = 0.001;
// Burley's fixed alpha of the clearcoat's Smith shadowing-masking
const CLEARCOAT_G_ALPHA: f32 = 0.25;
// Mitsuba's GTR1 eval returns 0 where D cos theta_m is below this (underflow at grazing normals)
const GTR1_D_COS_MIN: f32 = 1e-20;

fn principled_clearcoat_alpha(p: Principled) -> f32 {
    return mix(CLEARCOAT_ALPHA_ROUGH, CLEARCOAT_ALPHA_GLOSSY, p.clearcoat_gloss);
}

// GTR1 (Berry's) distribution of normals m, normalised so that D cos theta_m integrates to 1.
// Mitsuba's 1 + (alpha^2 - 1) cos^2 written as sin^2 + alpha^2 cos^2: near the peak of a glossy coat
// (alpha^2 ~ 1e-6) the former cancels to a few significant bits in f32.
fn gtr1_d(m: vec3<f32>, alpha: f32) -> f32 {
    let alpha2 = alpha * alpha;
    let d = (alpha2 - 1.0) / (PI * log(alpha2) * (m.x * m.x + m.y * m.y + alpha2 * m.z * m.z));
    return select(0.0, d, d * m.z > GTR1_D_COS_MIN);
}

// The density of sample_gtr1_normal's normals: D cos theta_m
fn pdf_gtr1_normal(m: vec3<f32>, alpha: f32) -> f32 {
    return select(m.z * gtr1_d(m, alpha), 0.0, m.z < 0.0);
}

fn sample_gtr1_normal(alpha: f32, u: vec2<f32>) -> vec3<f32> {
    let alpha2 = alpha * alpha;
    let cos2 = (1.0 - pow(alpha2, 1.0 - u.y)) / (1.0 - alpha2);
    let sin_theta = sqrt(max(0.0, 1.0 - cos2));
    let cos_theta = sqrt(max(0.0, cos2));
    let phi = TWO_PI * u.x;
    return vec3<f32>(cos(phi) * sin_theta, sin(phi) * sin_theta, cos_theta);
}

// Mitsuba's smith_ggx1: Smith's G1 for GGX of CLEARCOAT_G_ALPHA, 0 where v sees m's back
fn clearcoat_smith_g1(v: vec3<f32>, m: vec3<f32>) -> f32 {
    let cos2 = v.z * v.z;
    let tan2 = (1.0 - cos2) / cos2;
    let g = select(2.0 / (1.0 + sqrt(1.0 + CLEARCOAT_G_ALPHA * CLEARCOAT_G_ALPHA * tan2)), 1.0, v.z == 1.0);
    return select(g, 0.0, dot(v, m) * v.z <= 0.0);
}

// Its probability before normalisation (Mitsuba's clearcoat sampling rate 1)
fn principled_clearcoat_rate(p: Principled) -> f32 {
    return CLEARCOAT_WEIGHT * p.clearcoat;
}

// f cos_o for wi and wo above the surface, h their half vector (compatible with both)
fn principled_clearcoat_eval(p: Principled, wi: vec3<f32>, wo: vec3<f32>, h: vec3<f32>) -> f32 {
    if p.clearcoat <= 0.0 {
        return 0.0;
    }
    let fresnel = principled_schlick(vec3<f32>(CLEARCOAT_R0), dot(wi, h), p.eta).x;
    let g = clearcoat_smith_g1(wi, h) * clearcoat_smith_g1(wo, h);
    return CLEARCOAT_WEIGHT * p.clearcoat * fresnel * gtr1_d(h, principled_clearcoat_alpha(p)) * g * wo.z;
}

// The density of wo = reflect(-wi, principled_clearcoat_normal(p, u)) (h: its half vector)
fn principled_clearcoat_pdf(p: Principled, wo: vec3<f32>, h: vec3<f32>) -> f32 {
    return pdf_gtr1_normal(h, principled_clearcoat_alpha(p)) / (4.0 * abs(dot(wo, h)));
}

fn principled_clearcoat_normal(p: Principled, u: vec2<f32>) -> vec3<f32> {
    return sample_gtr1_normal(principled_clearcoat_alpha(p), u);
}
