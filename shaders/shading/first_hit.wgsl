// The surface a camera ray first hits, shaded as the path tracer shades it: the viewer's guides and the G-buffer.
//! include "generated/acceleration.wgsl"
// shading_normal, resolve_material and mapped_normal: the scene's smooth shading and textures, as
// the path tracer sees them at its first hit (the kernel variant's hooks)
//! include "generated/shading_normals.wgsl"
//! include "generated/textures.wgsl"
// vertex_colored: the material as it is unless the scene has vertex colours (vertex_colors_hook)
//! include "generated/vertex_colors.wgsl"

// Through each pixel's centre (and a lens's centre), so a pixel's first hit does not change from
// sample to sample.
const PIXEL_CENTRE: vec2<f32> = vec2<f32>(0.5, 0.5);

// `found` false where the ray left the scene. `normal`: the shading normal on the side facing the
// ray (both sides of a triangle look alike to the eye); `albedo`: the material's colour (an
// emitter's radiance); `material`: its index; `word`: the hit triangle's word (instance slot and
// triangle, `instance_slot`, `mesh_triangle`).
struct FirstHit {
    found: bool,
    distance: f32,
    position: vec3<f32>,
    normal: vec3<f32>,
    albedo: vec3<f32>,
    material: u32,
    word: u32,
}

// BLEND surfaces (surface_blocks) draw from rng_state: callers trace this before seeding it, or
// with xoshiro's zero state, which draws 0 forever, so every surface whose alpha is above 0 is seen.
fn first_hit(ray: Ray) -> FirstHit {
    let hit = closest_hit(ray, FLOAT_MAX, NO_TRIANGLE);
    if hit.triangle == NO_TRIANGLE {
        return FirstHit(false, 0.0, vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0u, NO_TRIANGLE);
    }
    let triangle = scene_triangle(hit.triangle);
    let normal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
    let p = ray.origin + hit.t * ray.direction;
    let material = vertex_colored(resolve_material(materials[triangle.material], triangle.material, hit.triangle, triangle, p), hit.triangle, triangle, p);
    let towards_viewer = -ray.direction;
    let interpolated = shading_normal(hit.triangle, triangle, p, normal, towards_viewer);
    let shading = mapped_normal(interpolated, material, triangle.material, hit.triangle, triangle, p, normal, towards_viewer);
    let facing = select(shading, -shading, dot(normal, ray.direction) > 0.0);
    return FirstHit(true, hit.t, p, facing, material.color, triangle.material, hit.triangle);
}
