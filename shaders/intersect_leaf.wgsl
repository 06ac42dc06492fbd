// The triangles of one leaf (or one flat-list box) against a ray: shared by both traversals.
//! include "scene_bindings.wgsl"
//! include "intersect_triangle.wgsl"

fn intersect_leaf(sheared: ShearedRay, node: BvhNode, skip_triangle: u32, hit: ptr<function, Hit>) {
    for (var i = node.left_or_first; i < node.left_or_first + node.triangle_count; i++) {
        if i == skip_triangle {
            continue;
        }
        let triangle = triangles[i];
        let t = intersect_triangle(sheared, triangle.v0, triangle.v1, triangle.v2, (*hit).t);
        if t < (*hit).t {
            *hit = Hit(t, i);
        }
    }
}
