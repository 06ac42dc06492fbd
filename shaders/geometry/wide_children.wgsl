// A 4-wide node's children against a ray: their entry distances, and nearer ones first (both traversals).
//! include "geometry/intersect_box.wgsl"
//! include "geometry/bvh_child_order.wgsl"
//! include "generated/texel_loaders.wgsl"

// Child k's (entry distance bits, child word): the shipped box test, FLOAT_MAX for an empty slot.
fn wide_child(ray: Ray, inverse_direction: vec3<f32>, wide: WideBvhNode, k: u32, t_max: f32) -> vec2<u32> {
    let bounds_min = vec3<f32>(wide.min_x[k], wide.min_y[k], wide.min_z[k]);
    let bounds_max = vec3<f32>(wide.max_x[k], wide.max_y[k], wide.max_z[k]);
    let t = intersect_box(ray.origin, inverse_direction, bounds_min, bounds_max, t_max);
    return vec2<u32>(bitcast<u32>(select(t, FLOAT_MAX, wide.children[k] == WIDE_EMPTY)), wide.children[k]);
}

fn is_hit(child: vec2<u32>) -> bool {
    return bitcast<f32>(child.x) != FLOAT_MAX;
}

// Leaves a, b in the order nearer first (an exact tie keeps them as they are).
fn order_pair(a: ptr<function, vec2<u32>>, b: ptr<function, vec2<u32>>) {
    let first = *a;
    let second = *b;
    let keep = bitcast<f32>(first.x) <= bitcast<f32>(second.x);
    *a = select(second, first, keep);
    *b = select(first, second, keep);
}
