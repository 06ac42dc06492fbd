// Experiment: traverse_bvh.wgsl with the nodes in a uniform buffer, its array sized for this scene (at most 64 KiB).
//! include "intersect_leaf.wgsl"
//! include "intersect_box.wgsl"
//! include "hit_queries.wgsl"
//! include "generated/traversal_stack.wgsl"

@group(0) @binding(2) var<uniform> nodes: array<BvhNode, __NODE_COUNT__>;

// A triangle along the ray closer than t_max, ignoring `skip_triangle` (the surface the ray
// leaves): the nearest one, or with `any_hit` the first one found. Misses return NO_TRIANGLE.
fn traverse(ray: Ray, t_max: f32, skip_triangle: u32, any_hit: bool) -> Hit {
    var hit = Hit(t_max, NO_TRIANGLE);
    let sheared = shear_ray(ray);
    let inverse_direction = safe_inverse_direction(ray.direction);
    var stack: array<u32, TRAVERSAL_STACK_SIZE>;
    var stack_size = 0u;
    var node_index = 0u;
    let root = nodes[0];
    if intersect_box(ray.origin, inverse_direction, root.bounds_min, root.bounds_max, hit.t) == FLOAT_MAX {
        return hit;
    }
    loop {
        traversal_steps++;
        let node = nodes[node_index];
        if node.triangle_count > 0u {
            if intersect_leaf(sheared, node, skip_triangle, any_hit, &hit) {
                break;
            }
        } else {
            let left = node.left_or_first;
            let left_node = nodes[left];
            let right_node = nodes[left + 1u];
            let t_left = intersect_box(ray.origin, inverse_direction, left_node.bounds_min, left_node.bounds_max, hit.t);
            let t_right = intersect_box(ray.origin, inverse_direction, right_node.bounds_min, right_node.bounds_max, hit.t);
            if t_left != FLOAT_MAX || t_right != FLOAT_MAX {
                let left_first = t_left <= t_right;
                let near = select(left + 1u, left, left_first);
                let far_hit = select(t_left, t_right, left_first) != FLOAT_MAX;
                if far_hit {
                    stack[stack_size] = select(left, left + 1u, left_first);
                    stack_size++;
                }
                node_index = near;
                continue;
            }
        }
        if stack_size == 0u {
            break;
        }
        stack_size--;
        node_index = stack[stack_size];
    }
    return hit;
}
