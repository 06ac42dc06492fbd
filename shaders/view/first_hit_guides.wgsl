// First-hit guides per pixel (normal, albedo, depth, BVH steps): debug views and the filter's edge stops.
//! include "generated/acceleration.wgsl"
//! include "generated/camera.wgsl"
//! include "view/guide_packing.wgsl"
// shading_normal, resolve_material and mapped_normal: the scene's smooth shading and textures, as
// the path tracer sees them at its first hit (the renderer's SceneVariant)
//! include "generated/shading_normals.wgsl"
//! include "generated/textures.wgsl"
// vertex_colored: the material as it is unless the scene has vertex colours (vertex_colors_hook)
//! include "generated/vertex_colors.wgsl"
//! include "generated/bindings/guides.wgsl"
//! include "generated/workgroup.wgsl"

// Through each pixel's centre (and a lens's centre), so the guides of a frame do not change from
// sample to sample.
const PIXEL_CENTRE: vec2<f32> = vec2<f32>(0.5, 0.5);

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    // BLEND surfaces (surface_blocks) draw from rng_state, never seeded here: xoshiro's zero
    // state draws 0 forever, so the guides see every surface whose alpha is above 0, frame after frame
    traversal_steps = 0u;
    let ray = camera_ray(id.xy, PIXEL_CENTRE, LENS_CENTRE);
    let hit = closest_hit(ray, FLOAT_MAX, NO_TRIANGLE);
    // depth 0 marks "nothing hit": the filter never mixes such pixels with surfaces
    var guide = Guide(vec3<f32>(0.0, 0.0, 1.0), 0.0, vec3<f32>(0.0), 0u);
    if hit.triangle != NO_TRIANGLE {
        let triangle = scene_triangle(hit.triangle);
        let normal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
        let p = ray.origin + hit.t * ray.direction;
        let material = vertex_colored(resolve_material(materials[triangle.material], triangle.material, hit.triangle, triangle, p), hit.triangle, triangle, p);
        let towards_viewer = -ray.direction;
        let interpolated = shading_normal(hit.triangle, triangle, p, normal, towards_viewer);
        let shading = mapped_normal(interpolated, material, triangle.material, hit.triangle, triangle, p, normal, towards_viewer);
        // the side facing the camera: both sides of a triangle look alike to the eye
        guide.normal = select(shading, -shading, dot(normal, ray.direction) > 0.0);
        guide.depth = hit.t;
        guide.albedo = material.color;
    }
    guide.steps = traversal_steps;
    textureStore(guides, id.xy, pack_guide(guide));
}
