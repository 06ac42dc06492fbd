// Two-level traversal over 4-wide nodes: the top level over instances (record 0), then each one's mesh in object space.
//! include "geometry/intersect_triangle.wgsl"
//! include "geometry/hit_queries.wgsl"
//! include "geometry/scene_bindings.wgsl"
//! include "geometry/wide_children.wgsl"
//! include "generated/traversal_stack.wgsl"
//! include "generated/instancing.wgsl"
// surface_blocks: alpha cut-outs, stochastic transparency and single-sided surfaces (alpha_hook)
//! include "generated/alpha.wgsl"
//
// The scene's own shapes are one more top-level item (slot 0, identity), so this is the only
// traversal such a scene runs. Same contract as the BVH's traverse; the hit's `triangle` is a hit
// word (instances.wgsl), which everything downstream reads through scene_triangle and mesh_triangle.

// One stack for both levels: a mesh's entries go above those of the top level that reached it
// (InstanceRecords.stack_entries sizes it). At module scope, as the BVH traversal's.
var<private> stack: array<u32, TRAVERSAL_STACK_SIZE>;

// The node on top of the stack, popped; WIDE_EMPTY where it holds nothing above `base`.
fn pop(base: u32, stack_size: ptr<function, u32>) -> u32 {
    if *stack_size == base {
        return WIDE_EMPTY;
    }
    *stack_size -= 1u;
    return stack[*stack_size];
}

// Where traversal goes from interior record `node`: its nearest child the ray enters (the others
// pushed, farthest first, so nearer ones come off first), else the node popped.
fn descend(ray: Ray, inverse_direction: vec3<f32>, node: u32, t_max: f32, base: u32, stack_size: ptr<function, u32>) -> u32 {
    traversal_steps++;
    count_lanes(LOOP_TRAVERSAL);
    count_lanes(LOOP_INTERIOR);
    let wide = load_WideBvhNode(nodes, node);
    var c0 = wide_child(ray, inverse_direction, wide, 0u, t_max);
    var c1 = wide_child(ray, inverse_direction, wide, 1u, t_max);
    var c2 = wide_child(ray, inverse_direction, wide, 2u, t_max);
    var c3 = wide_child(ray, inverse_direction, wide, 3u, t_max);
    order_children(&c0, &c1, &c2, &c3);
    if !is_hit(c0) {
        return pop(base, stack_size);
    }
    for (var k = 0u; k < 3u; k++) {
        let child = select(select(c1, c2, k == 1u), c3, k == 0u);
        if is_hit(child) {
            stack[*stack_size] = child.y;
            *stack_size += 1u;
        }
    }
    return c0.y;
}

fn leaf_first(node: u32) -> u32 {
    return (node & ~WIDE_LEAF) >> WIDE_COUNT_BITS;
}

fn leaf_count(node: u32) -> u32 {
    return (node & WIDE_COUNT_MASK) + 1u;
}

// The leaf's triangles of the mesh in `slot` against `ray` in its object space, as intersect_leaf
// does in the world: true where an any-hit query is answered.
fn intersect_mesh_leaf(ray: Ray, sheared: ShearedRay, node: u32, slot: u32, skip_triangle: u32, any_hit: bool, hit: ptr<function, Hit>) -> bool {
    let first = leaf_first(node);
    for (var i = first; i < first + leaf_count(node); i++) {
        count_lanes(LOOP_TRIANGLE);
        let word = (slot << INSTANCE_TRIANGLE_BITS) | i;
        if word == skip_triangle {
            continue;
        }
        let triangle = load_Triangle(triangles, i);
        let t = intersect_triangle(sheared, triangle.v0, triangle.v1, triangle.v2, (*hit).t);
        if t < (*hit).t && surface_blocks(ray, t, word, triangle) {
            *hit = Hit(t, word);
            if any_hit {
                return true;
            }
        }
    }
    return false;
}

// The mesh whose tree starts at record `root`, against `ray` in its object space, its stack above
// `base`: true where an any-hit query is answered.
fn traverse_mesh(ray: Ray, root: u32, slot: u32, base: u32, skip_triangle: u32, any_hit: bool, hit: ptr<function, Hit>) -> bool {
    let sheared = shear_ray(ray);
    let inverse_direction = safe_inverse_direction(ray.direction);
    var stack_size = base;
    var node = root;
    loop {
        while (node & WIDE_LEAF) == 0u {
            node = descend(ray, inverse_direction, node, (*hit).t, base, &stack_size);
        }
        if node == WIDE_EMPTY {
            return false;
        }
        traversal_steps++;
        count_lanes(LOOP_TRAVERSAL);
        count_lanes(LOOP_LEAF);
        if intersect_mesh_leaf(ray, sheared, node, slot, skip_triangle, any_hit, hit) {
            return true;
        }
        node = pop(base, &stack_size);
    }
    return false; // not reached: WGSL asks for a return at the end
}

fn traverse(ray: Ray, t_max: f32, skip_triangle: u32, any_hit: bool) -> Hit {
    var hit = Hit(t_max, NO_TRIANGLE);
    let inverse_direction = safe_inverse_direction(ray.direction);
    var stack_size = 0u;
    var node = 0u;
    loop {
        while (node & WIDE_LEAF) == 0u {
            node = descend(ray, inverse_direction, node, hit.t, 0u, &stack_size);
        }
        if node == WIDE_EMPTY {
            return hit;
        }
        traversal_steps++;
        count_lanes(LOOP_TRAVERSAL);
        count_lanes(LOOP_LEAF);
        let first = leaf_first(node);
        for (var k = first; k < first + leaf_count(node); k++) {
            let instance = instances[k];
            var local = ray;
            if instance.slot != 0u {
                local = object_ray(instance, ray);
            }
            if traverse_mesh(local, instance.root, instance.slot, stack_size, skip_triangle, any_hit, &hit) {
                return hit;
            }
        }
        node = pop(0u, &stack_size);
    }
    return hit; // not reached
}
