// One entry point per operation over all materials; two-sided materials mirror wi to +z first.
//! include "generated/structs.wgsl"
//! include "materials/diffuse.wgsl"
//! include "materials/glossy.wgsl"
//! include "materials/glass.wgsl"

// Diffuse and glossy look the same from both sides (Mitsuba's `twosided`); glass has an inside.
fn is_two_sided(material: Material) -> bool {
    return material.kind != MATERIAL_GLASS;
}

fn flip_z(v: vec3<f32>, flip: bool) -> vec3<f32> {
    return select(v, vec3<f32>(v.x, v.y, -v.z), flip);
}

fn bsdf_sample(material: Material, wi: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    let flip = is_two_sided(material) && wi.z < 0.0;
    let w = flip_z(wi, flip);
    var sample = no_bsdf_sample();
    switch material.kind {
        case MATERIAL_DIFFUSE: { sample = diffuse_sample(material.color, w, u); }
        case MATERIAL_GLOSSY: { sample = glossy_sample(material.color, material.alpha, w, u); }
        case MATERIAL_GLASS: { sample = glass_sample(material.color, material.ior, w, u_lobe); }
        default: {}
    }
    sample.direction = flip_z(sample.direction, flip);
    return sample;
}

fn bsdf_eval(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let flip = is_two_sided(material) && wi.z < 0.0;
    let a = flip_z(wi, flip);
    let b = flip_z(wo, flip);
    switch material.kind {
        case MATERIAL_DIFFUSE: { return diffuse_eval(material.color, a, b); }
        case MATERIAL_GLOSSY: { return glossy_eval(material.color, material.alpha, a, b); }
        case MATERIAL_GLASS: { return glass_eval(a, b); }
        default: { return vec3<f32>(0.0); }
    }
}

fn bsdf_pdf(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let flip = is_two_sided(material) && wi.z < 0.0;
    let a = flip_z(wi, flip);
    let b = flip_z(wo, flip);
    switch material.kind {
        case MATERIAL_DIFFUSE: { return diffuse_pdf(a, b); }
        case MATERIAL_GLOSSY: { return glossy_pdf(material.alpha, a, b); }
        case MATERIAL_GLASS: { return glass_pdf(a, b); }
        default: { return 0.0; }
    }
}
