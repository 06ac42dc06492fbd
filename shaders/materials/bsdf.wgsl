// One entry point per operation over the scene's materials; two-sided materials mirror wi to +z first.
//! include "generated/structs.wgsl"
// the local shading frame every BSDF works in, needed by callers even when no material includes it
//! include "sampling/warps.wgsl"
// material_sample/_eval/_pdf and material_is_two_sided (Mitsuba's `twosided`: the same BSDF seen
// from below), generated for the material kinds the scene uses (material_dispatch)
//! include "generated/materials.wgsl"

fn flip_z(v: vec3<f32>, flip: bool) -> vec3<f32> {
    return select(v, vec3<f32>(v.x, v.y, -v.z), flip);
}

fn bsdf_sample(material: Material, wi: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    let flip = material_is_two_sided(material) && wi.z < 0.0;
    var sample = material_sample(material, flip_z(wi, flip), u, u_lobe);
    sample.direction = flip_z(sample.direction, flip);
    return sample;
}

fn bsdf_eval(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let flip = material_is_two_sided(material) && wi.z < 0.0;
    return material_eval(material, flip_z(wi, flip), flip_z(wo, flip));
}

fn bsdf_pdf(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let flip = material_is_two_sided(material) && wi.z < 0.0;
    return material_pdf(material, flip_z(wi, flip), flip_z(wo, flip));
}
