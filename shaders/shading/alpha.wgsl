// surface_blocks: which surfaces a ray may pass through (Principled's alpha_mode and double_sided).
// The traversal's triangle test consults it (alpha_hook), so closest-hit and shadow rays agree: a
// cut-out leaf lets light through where it lets the camera see through.
//! include "shading/textures.wgsl"
//! include "sampling/rng.wgsl"
//! include "generated/vertex_colors.wgsl"

// Whether triangle `triangle_index`, hit by `ray` at distance t, stops the ray. MASK: the alpha
// (material alpha x the vertex colours' x the base colour texture's) at the hit against the
// cutoff. BLEND: stochastic transparency, blocking with probability alpha from the path's own
// random numbers, so each
// sample is deterministic and the average over samples is the blended one. A single-sided surface
// is invisible from behind, as backface culling makes it in Blender and three.js: a path tracer
// has no "back" to shade, and a closed mesh's inside faces are never what a camera outside sees.
fn surface_blocks(ray: Ray, t: f32, triangle_index: u32, triangle: Triangle) -> bool {
    let slots = material_textures[triangle.material];
    if slots.double_sided == 0u && dot(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0), ray.direction) > 0.0 {
        return false;
    }
    if slots.alpha_mode == ALPHA_OPAQUE {
        return true;
    }
    let p = ray.origin + t * ray.direction;
    var alpha = slots.alpha * vertex_alpha(triangle_index, triangle, p);
    if slots.base_color != NO_TEXTURE {
        alpha *= texture_sample(slots.base_color, surface_uv(triangle_index, triangle, p)).a;
    }
    if slots.alpha_mode == ALPHA_MASK {
        return alpha >= slots.alpha_cutoff;
    }
    return rng_next_f32() < alpha;
}
