// Principled's parameters as its lobes read them, their weights and Mitsuba's Schlick helpers.
//! include "generated/structs.wgsl"

// Mitsuba's calc_dist_params floors GGX alpha = roughness^2 here: roughness 0 is a near-mirror.
const PRINCIPLED_ALPHA_MIN: f32 = 0.001;

struct Principled {
    base_color: vec3<f32>,
    metallic: f32,
    roughness: f32,
    // index of refraction of the dielectric specular layer, outside 1
    eta: f32,
    spec_trans: f32,
    clearcoat: f32,
    clearcoat_gloss: f32,
    sheen: f32,
    sheen_tint: f32,
    anisotropic: f32,
}

// One reader per parameter of the base lobes, so that a textured parameter replaces its reader by a
// texture lookup (the clearcoat's, sheen's and anisotropy's take no textures).
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

fn principled_spec_trans(material: Material) -> f32 {
    return material.spec_trans;
}

fn principled_parameters(material: Material) -> Principled {
    return Principled(
        principled_base_color(material),
        principled_metallic(material),
        principled_roughness(material),
        principled_eta(material),
        principled_spec_trans(material),
        material.clearcoat,
        material.clearcoat_gloss,
        material.sheen,
        material.sheen_tint,
        material.anisotropic,
    );
}

// Weight of the reflective (diffuse) lobes
fn principled_brdf_weight(p: Principled) -> f32 {
    return (1.0 - p.metallic) * (1.0 - p.spec_trans);
}

// Weight of the transmissive lobe
fn principled_bsdf_weight(p: Principled) -> f32 {
    return (1.0 - p.metallic) * p.spec_trans;
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
