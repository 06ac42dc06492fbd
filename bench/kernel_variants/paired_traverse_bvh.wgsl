// Experiment: traversal over paired records (paired_nodes.py: both children's boxes in one record) from texels.
//! include "intersect_leaf.wgsl"
//! include "generated/texel_loaders.wgsl"
//! include "intersect_box.wgsl"
//! include "hit_queries.wgsl"
//! include "generated/traversal_stack.wgsl"

@group(0) @binding(2) var node_texels: texture_2d<u32>;

fn box_entry(ray: Ray, inverse_direction: vec3<f32>, bounds_min: vec4<u32>, bounds_max: vec4<u32>, t_max: f32) -> f32 {
    return intersect_box(ray.origin, inverse_direction, bitcast<vec3<f32>>(bounds_min.xyz), bitcast<vec3<f32>>(bounds_max.xyz), t_max);
}

fn traverse(ray: Ray, t_max: f32, skip_triangle: u32, any_hit: bool) -> Hit {
    var hit = Hit(t_max, NO_TRIANGLE);
    let sheared = shear_ray(ray);
    let inverse_direction = safe_inverse_direction(ray.direction);
    // (ref, count) of the nodes still to visit
    var stack: array<vec2<u32>, TRAVERSAL_STACK_SIZE>;
    var stack_size = 0u;
    let root_min = texel_at(node_texels, 0u);
    let root_max = texel_at(node_texels, 1u);
    if box_entry(ray, inverse_direction, root_min, root_max, hit.t) == FLOAT_MAX {
        return hit;
    }
    var node = vec2<u32>(root_min.w, root_max.w);
    loop {
        traversal_steps++;
        if node.y > 0u {
            if intersect_leaf(sheared, BvhNode(vec3<f32>(0.0), node.x, vec3<f32>(0.0), node.y), skip_triangle, any_hit, &hit) {
                break;
            }
        } else {
            let base = 4u * node.x;
            let a_min = texel_at(node_texels, base);
            let a_max = texel_at(node_texels, base + 1u);
            let b_min = texel_at(node_texels, base + 2u);
            let b_max = texel_at(node_texels, base + 3u);
            let t_a = box_entry(ray, inverse_direction, a_min, a_max, hit.t);
            let t_b = box_entry(ray, inverse_direction, b_min, b_max, hit.t);
            if t_a != FLOAT_MAX || t_b != FLOAT_MAX {
                let a_first = t_a <= t_b;
                let a = vec2<u32>(a_min.w, a_max.w);
                let b = vec2<u32>(b_min.w, b_max.w);
                if select(t_a, t_b, a_first) != FLOAT_MAX {
                    stack[stack_size] = select(a, b, a_first);
                    stack_size++;
                }
                node = select(b, a, a_first);
                continue;
            }
        }
        if stack_size == 0u {
            break;
        }
        stack_size--;
        node = stack[stack_size];
    }
    return hit;
}
