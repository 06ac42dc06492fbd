// BVH traversal over 4-wide nodes (WideBVH), closest hit and any hit: a one-word stack, nearer children first.
//! include "geometry/intersect_leaf.wgsl"
//! include "geometry/intersect_box.wgsl"
//! include "geometry/hit_queries.wgsl"
//! include "generated/texel_loaders.wgsl"
//! include "geometry/wide_children.wgsl"
//! include "generated/traversal_stack.wgsl"

// The scene group's `nodes` are texels of 4-wide records here (scene_group): texture
// loads are the fast kind on lavapipe, and four children's boxes a record save steps
// (bench/README.md's optimization log).

// A triangle along the ray closer than t_max, ignoring `skip_triangle` (the surface the ray
// leaves): the nearest one, or with `any_hit` the first one found. Misses return NO_TRIANGLE.
// At most WIDTH - 1 entries per wide level: collapse shows every tree fits BVH_STACK_SIZE; the
// renderer compiles only what its tree needs (traversal_stack_size). At module
// scope because WGSL zero-fills a variable where it is declared: here once per invocation, in
// traverse() at every traversal (`python -m bench.kernel_profile --variants function_stack`
// measures the difference). traverse() is never re-entered.
var<private> stack: array<u32, TRAVERSAL_STACK_SIZE>;

fn traverse(ray: Ray, t_max: f32, skip_triangle: u32, any_hit: bool) -> Hit {
    var hit = Hit(t_max, NO_TRIANGLE);
    let sheared = shear_ray(ray);
    let inverse_direction = safe_inverse_direction(ray.direction);
    var stack_size = 0u;
    var node = 0u; // record 0 holds the root's children
    // Interior nodes in a loop of their own until this lane reaches a leaf, then that leaf
    // (Aila and Laine's "while-while"): lanes run in lockstep test their leaves' triangles
    // together instead of each alone while the others wait. Every ray visits the same nodes in
    // the same order as one loop taking one node per pass would.
    loop {
        loop {
            if (node & WIDE_LEAF) != 0u {
                break;
            }
            traversal_steps++;
            count_lanes(LOOP_TRAVERSAL);
            count_lanes(LOOP_INTERIOR);
            let wide = load_WideBvhNode(nodes, node);
            var c0 = wide_child(ray, inverse_direction, wide, 0u, hit.t);
            var c1 = wide_child(ray, inverse_direction, wide, 1u, hit.t);
            var c2 = wide_child(ray, inverse_direction, wide, 2u, hit.t);
            var c3 = wide_child(ray, inverse_direction, wide, 3u, hit.t);
            order_children(&c0, &c1, &c2, &c3);
            if is_hit(c0) {
                // pushed farthest first, so that the nearer ones come off the stack first
                if is_hit(c3) {
                    stack[stack_size] = c3.y;
                    stack_size++;
                }
                if is_hit(c2) {
                    stack[stack_size] = c2.y;
                    stack_size++;
                }
                if is_hit(c1) {
                    stack[stack_size] = c1.y;
                    stack_size++;
                }
                node = c0.y;
                continue;
            }
            if stack_size == 0u {
                return hit;
            }
            stack_size--;
            node = stack[stack_size];
        }
        traversal_steps++;
        count_lanes(LOOP_TRAVERSAL);
        count_lanes(LOOP_LEAF);
        let first = (node & ~WIDE_LEAF) >> WIDE_COUNT_BITS;
        let count = (node & WIDE_COUNT_MASK) + 1u;
        if intersect_leaf(ray, sheared, BvhNode(vec3<f32>(0.0), first, vec3<f32>(0.0), count), skip_triangle, any_hit, &hit) {
            return hit;
        }
        if stack_size == 0u {
            return hit;
        }
        stack_size--;
        node = stack[stack_size];
    }
    // not reached: every way out of the loop returns (WGSL asks for a return at the end)
    return hit;
}
