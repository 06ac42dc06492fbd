// First-hit guides per pixel (normal, albedo, depth, BVH steps): debug views and the filter's edge stops.
//! include "shading/first_hit.wgsl"
//! include "generated/camera.wgsl"
//! include "view/guide_packing.wgsl"
//! include "generated/bindings/guides.wgsl"
//! include "generated/workgroup.wgsl"

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    // rng_state is never seeded here (first_hit: BLEND surfaces)
    traversal_steps = 0u;
    let hit = first_hit(camera_ray(id.xy, PIXEL_CENTRE, LENS_CENTRE));
    // depth 0 marks "nothing hit": the filter never mixes such pixels with surfaces
    var guide = Guide(vec3<f32>(0.0, 0.0, 1.0), 0.0, vec3<f32>(0.0), 0u);
    if hit.found {
        guide = Guide(hit.normal, hit.distance, hit.albedo, 0u);
    }
    guide.steps = traversal_steps;
    textureStore(guides, id.xy, pack_guide(guide));
}
