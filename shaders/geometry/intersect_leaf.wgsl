// The triangles of one leaf (or one flat-list box) against a ray: shared by both traversals.
//! include "geometry/scene_bindings.wgsl"
//! include "geometry/intersect_triangle.wgsl"
// surface_blocks: alpha cut-outs, stochastic transparency and single-sided surfaces (alpha_hook)
//! include "generated/alpha.wgsl"

// Updates `hit` with the nearest triangle of the leaf; with `any_hit`, stops at the first one and
// returns true (a shadow ray needs no nearest occluder). A triangle the ray passes through (a
// cut-out texel, a single-sided surface from behind) is no hit.
fn intersect_leaf(ray: Ray, sheared: ShearedRay, node: BvhNode, skip_triangle: u32, any_hit: bool, hit: ptr<function, Hit>) -> bool {
    for (var i = node.left_or_first; i < node.left_or_first + node.triangle_count; i++) {
        count_lanes(LOOP_TRIANGLE);
        if i == skip_triangle {
            continue;
        }
        let triangle = scene_triangle(i);
        let t = intersect_triangle(sheared, triangle.v0, triangle.v1, triangle.v2, (*hit).t);
        if t < (*hit).t && surface_blocks(ray, t, i, triangle) {
            *hit = Hit(t, i);
            if any_hit {
                return true;
            }
        }
    }
    return false;
}
