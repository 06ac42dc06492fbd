// Experiment: intersect_leaf.wgsl reading the triangles' corners from texels (binding 8).
//! include "scene_bindings.wgsl"
//! include "intersect_triangle.wgsl"
//! include "generated/texel_loaders.wgsl"

@group(0) @binding(8) var triangle_texels: texture_2d<u32>;

fn intersect_leaf(sheared: ShearedRay, node: BvhNode, skip_triangle: u32, any_hit: bool, hit: ptr<function, Hit>) -> bool {
    for (var i = node.left_or_first; i < node.left_or_first + node.triangle_count; i++) {
        if i == skip_triangle {
            continue;
        }
        let v0 = bitcast<vec3<f32>>(texel_at(triangle_texels, 3u * i).xyz);
        let v1 = bitcast<vec3<f32>>(texel_at(triangle_texels, 3u * i + 1u).xyz);
        let v2 = bitcast<vec3<f32>>(texel_at(triangle_texels, 3u * i + 2u).xyz);
        let t = intersect_triangle(sheared, v0, v1, v2, (*hit).t);
        if t < (*hit).t {
            *hit = Hit(t, i);
            if any_hit {
                return true;
            }
        }
    }
    return false;
}
