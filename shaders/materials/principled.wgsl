// Principled: Mitsuba 3's `principled` BSDF (Burley's Disney BRDF) with anisotropic, sheen,
// clearcoat, spec_tint, flatness and spec_trans 0: a Disney diffuse lobe with retro-reflection
// and a GGX specular lobe whose Fresnel mixes the exact dielectric one (eta) and Schlick's about
// base_color by metallic. eval, pdf and sample transcribe Mitsuba's src/bsdfs/principled.cpp and
// principledhelpers.h for these parameters, so that renders match Mitsuba's references.
//! include "sampling.wgsl"
//! include "bsdf_sample.wgsl"
//! include "materials/glossy.wgsl"
//! include "materials/glass.wgsl"

// Mitsuba's calc_dist_params floors GGX alpha = roughness^2 here: roughness 0 is a near-mirror.
const PRINCIPLED_ALPHA_MIN: f32 = 0.001;

struct Principled {
    base_color: vec3<f32>,
    metallic: f32,
    roughness: f32,
    // index of refraction of the dielectric specular layer, outside 1
    eta: f32,
}

// One reader per parameter, so that a textured parameter replaces its reader by a texture lookup.
fn principled_base_color(material: Material) -> vec3<f32> {
    return material.color;
}

fn principled_metallic(material: Material) -> f32 {
    return material.metallic;
}

fn principled_roughness(material: Material) -> f32 {
    return material.alpha;
}

fn principled_eta(material: Material) -> f32 {
    return material.ior;
}

fn principled_parameters(material: Material) -> Principled {
    return Principled(
        principled_base_color(material),
        principled_metallic(material),
        principled_roughness(material),
        principled_eta(material),
    );
}

fn principled_alpha(p: Principled) -> f32 {
    return max(PRINCIPLED_ALPHA_MIN, p.roughness * p.roughness);
}

// (1 - cos)^5, the weight of Schlick's approximation
fn schlick_weight(cos_theta: f32) -> f32 {
    let m = clamp(1.0 - cos_theta, 0.0, 1.0);
    let m2 = m * m;
    return m2 * m2 * m;
}

// Mitsuba's calc_schlick for a microfacet seen from outside (cos_theta_i >= 0): Schlick's
// approximation about r0, weighted by the angle on the denser side (the refracted one where eta < 1).
fn principled_schlick(r0: vec3<f32>, cos_theta_i: f32, eta: f32) -> vec3<f32> {
    let cos_t2 = 1.0 - (1.0 - cos_theta_i * cos_theta_i) / (eta * eta);
    let cos_denser = select(sqrt(max(0.0, cos_t2)), cos_theta_i, eta > 1.0);
    return mix(vec3<f32>(schlick_weight(cos_denser)), vec3<f32>(1.0), r0);
}

// Probability of drawing the diffuse lobe: Mitsuba weighs specular 1 against diffuse 1 - metallic.
fn principled_diffuse_probability(p: Principled) -> f32 {
    let diffuse = 1.0 - p.metallic;
    return diffuse / (1.0 + diffuse);
}

// GGX reflection of half vector h, f cos_o: principled_fresnel D G / (4 wi.z).
fn principled_specular(p: Principled, wi: vec3<f32>, wo: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let alpha = principled_alpha(p);
    let cos_ih = dot(wi, h);
    let dielectric = fresnel_dielectric(cos_ih, p.eta).reflectance;
    let fresnel = mix(vec3<f32>(dielectric), principled_schlick(p.base_color, cos_ih, p.eta), p.metallic);
    let g = ggx_smith_g1(wi, h, alpha) * ggx_smith_g1(wo, h, alpha);
    return fresnel * (ggx_d(h, alpha) * g / (4.0 * wi.z));
}

// Burley's diffuse with retro-reflection, f cos_o, weighted by 1 - metallic.
fn principled_diffuse(p: Principled, wi: vec3<f32>, wo: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let f_o = schlick_weight(wo.z);
    let f_i = schlick_weight(wi.z);
    let lambert = (1.0 - 0.5 * f_i) * (1.0 - 0.5 * f_o);
    let cos_d = dot(h, wo);
    let r_r = 2.0 * p.roughness * cos_d * cos_d;
    let retro = r_r * (f_o + f_i + f_o * f_i * (r_r - 1.0));
    return p.base_color * ((1.0 - p.metallic) * wo.z * INV_PI * (lambert + retro));
}

fn principled_eval(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= COS_MIN || wo.z <= COS_MIN {
        return vec3<f32>(0.0);
    }
    let p = principled_parameters(material);
    let h = normalize(wi + wo);
    return principled_specular(p, wi, wo, h) + principled_diffuse(p, wi, wo, h);
}

fn principled_pdf(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wi.z <= COS_MIN || wo.z <= COS_MIN {
        return 0.0;
    }
    let p = principled_parameters(material);
    let diffuse = principled_diffuse_probability(p);
    let specular = pdf_ggx_reflection(wi, normalize(wi + wo), principled_alpha(p));
    return (1.0 - diffuse) * specular + diffuse * pdf_cosine_hemisphere(wo.z);
}

// One lobe drawn by u_lobe, weighted by the whole BSDF over the mixture's density, as Mitsuba does.
fn principled_sample(material: Material, wi: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    if wi.z <= COS_MIN {
        return no_bsdf_sample();
    }
    let p = principled_parameters(material);
    var wo: vec3<f32>;
    if u_lobe < principled_diffuse_probability(p) {
        wo = sample_cosine_hemisphere(u);
    } else {
        wo = reflect(-wi, sample_ggx_visible_normal(wi, principled_alpha(p), u));
    }
    let pdf = principled_pdf(material, wi, wo);
    if pdf <= 0.0 {
        return no_bsdf_sample();
    }
    return BsdfSample(wo, principled_eval(material, wi, wo) / pdf, pdf, false, 1.0);
}
