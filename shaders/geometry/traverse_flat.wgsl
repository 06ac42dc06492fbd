// Closest-hit over trac0r's flat list of per-shape boxes: every box is tested, then its triangles.
//! include "geometry/intersect_leaf.wgsl"
//! include "geometry/intersect_box.wgsl"
//! include "geometry/hit_queries.wgsl"

// The scene group's `nodes` are a storage array of BvhNode here (scene_group).

// Same contract as the BVH's traverse, so the path tracer includes either one.
fn traverse(ray: Ray, t_max: f32, skip_triangle: u32, any_hit: bool) -> Hit {
    var hit = Hit(t_max, NO_TRIANGLE);
    let sheared = shear_ray(ray);
    let inverse_direction = safe_inverse_direction(ray.direction);
    for (var n = 0u; n < frame.node_count; n++) {
        traversal_steps++;
        count_lanes(LOOP_TRAVERSAL);
        let node = nodes[n];
        if intersect_box(ray.origin, inverse_direction, node.bounds_min, node.bounds_max, hit.t) == FLOAT_MAX {
            continue;
        }
        if intersect_leaf(ray, sheared, node, skip_triangle, any_hit, &hit) {
            break;
        }
    }
    return hit;
}
