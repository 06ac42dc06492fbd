// The two questions an integrator asks a traversal: the nearest hit, and whether a ray is blocked.
//! include "generated/structs.wgsl"
//! include "geometry/ray.wgsl"
//! include "generated/ray_count.wgsl"
//
// Each traversal (the BVH's, the flat list's) defines `traverse(ray, t_max, skip_triangle, any_hit) -> Hit`
// and includes this file.

// Nodes visited by traversals of this invocation so far, for the viewer's heat map (its guides' steps).
// Kernels that never read it pay nothing measurable: on lavapipe the path tracer ran as fast
// with the increment as without it (alternating runs, differences within the run-to-run noise).
var<private> traversal_steps: u32;

fn closest_hit(ray: Ray, t_max: f32, skip_triangle: u32) -> Hit {
    count_ray(RAY_CLOSEST_HIT);
    return traverse(ray, t_max, skip_triangle, false);
}

// Whether anything but `skip_triangle` lies on the ray before t_max (a shadow ray's test).
fn occluded(ray: Ray, t_max: f32, skip_triangle: u32) -> bool {
    count_ray(RAY_SHADOW);
    return traverse(ray, t_max, skip_triangle, true).triangle != NO_TRIANGLE;
}
