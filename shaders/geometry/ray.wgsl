// Rays, hit records, and the offset that lets a ray leave a surface without hitting it again.
//! include "common/constants.wgsl"

struct Ray {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

struct Hit {
    t: f32,
    triangle: u32,
}

fn max_component(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// Start a ray at `p` on a triangle with corners v0, v1, v2 and unit normal `normal`, moved off
// the plane towards `direction`. The traversal also skips the triangle itself, so the offset only
// has to clear neighbours sharing an edge or corner.
fn offset_ray_origin(p: vec3<f32>, normal: vec3<f32>, direction: vec3<f32>, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> vec3<f32> {
    let magnitude = max_component(max(max(abs(v0), abs(v1)), max(abs(v2), abs(p))));
    let side = select(-1.0, 1.0, dot(normal, direction) > 0.0);
    return p + normal * (side * RAY_OFFSET_RELATIVE * magnitude);
}
