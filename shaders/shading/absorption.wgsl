// Beer-Lambert absorption inside a material (KHR_materials_volume): segment_transmittance.
//! include "generated/structs.wgsl"

// What is left of light that travelled `distance` along unit `direction` to a hit on a surface of
// `material` with geometric normal `geometric`. Arriving on its back (the inside: the side the
// normal points away from) the segment ran inside the material, which absorbs material.absorption
// (sigma_a, at most ABSORPTION_MAX: finite, so never inf x 0) per unit length; on its front it ran
// outside, where nothing absorbs. What the segment started on does not matter: a closed mesh with
// nothing inside it, the only arrangement supported (wgputrace.scene.materials.volume).
fn segment_transmittance(material: Material, geometric: vec3<f32>, direction: vec3<f32>, distance: f32) -> vec3<f32> {
    if dot(direction, geometric) <= 0.0 {
        return vec3<f32>(1.0);
    }
    return exp(-material.absorption * distance);
}
