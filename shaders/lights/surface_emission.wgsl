// surface_emission: the light materials emit through their MATERIAL_TEXTURES record (emission_hook).
// Principled's emission x emission_strength x its emission texture, as the light sampler and the path see it.
//! include "shading/textures.wgsl"

// The radiance leaving triangle `triangle_index` at `p` along -direction (direction: from the
// viewer or receiver towards p): both sides, as an Emitter, except a single-sided surface, which
// is invisible and dark from behind (surface_blocks).
fn surface_emission(material_index: u32, triangle_index: u32, triangle: Triangle, p: vec3<f32>, direction: vec3<f32>) -> vec3<f32> {
    let slots = material_textures[material_index];
    let behind = dot(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0), direction) > 0.0;
    if all(slots.emitted == vec3<f32>(0.0)) || (slots.double_sided == 0u && behind) {
        return vec3<f32>(0.0);
    }
    if slots.emission == NO_TEXTURE {
        return slots.emitted;
    }
    return slots.emitted * texture_sample(slots.emission, surface_uv(triangle_index, triangle, p)).rgb;
}

// The light table's weight per unit area of triangle `triangle_index` (its emitted luminance over
// its footprint in the emission texture: footprint_means), for the density with
// which the light sampler picks its points.
fn surface_light_density(triangle_index: u32) -> f32 {
    return triangle_light_densities[mesh_triangle(triangle_index)];
}

// Whether triangles of material `material_index` emit from their back (the side
// cross(v1 - v0, v2 - v0) points away from) as from their front: all but single-sided surfaces.
fn surface_emits_both_sides(material_index: u32) -> bool {
    return material_textures[material_index].double_sided != 0u;
}
