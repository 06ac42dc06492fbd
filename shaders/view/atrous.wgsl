// One pass of the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010) on demodulated radiance.
//! include "generated/structs.wgsl"
//! include "generated/view_structs.wgsl"
//! include "generated/display_constants.wgsl"
//! include "common/constants.wgsl"
//! include "view/guide_packing.wgsl"
//! include "generated/bindings/atrous.wgsl"
//! include "generated/workgroup.wgsl"
//
// Each pass spreads the 5x5 B3-spline kernel `step` pixels apart (1, 2, 4, ...), so a few passes
// cover a wide footprint at 25 taps each. Taps are weighted down across edges of the first hit's
// normal, depth and albedo, and the weights are normalised: a flat region keeps its level.
// Guides and colours are textures: a tap costs two texel loads (storage-buffer loads cost several
// times more on CPU adapters: TrackedTexels).

const B3_SPLINE = array<f32, 3>(0.375, 0.25, 0.0625);

fn edge_weight(centre: Guide, tap: Guide) -> f32 {
    let centre_hit = centre.depth > 0.0;
    if centre_hit != (tap.depth > 0.0) {
        return 0.0;
    }
    if !centre_hit {
        return 1.0;
    }
    let normal = pow(max(dot(centre.normal, tap.normal), 0.0), params.normal_power);
    // depth differences relative to the distance and to the tap's offset: a slanted floor far
    // away changes depth faster per pixel than a wall in front
    let depth = exp(-abs(centre.depth - tap.depth) / (params.depth_sigma * centre.depth * f32(params.step)));
    let albedo_difference = centre.albedo - tap.albedo;
    let albedo = exp(-dot(albedo_difference, albedo_difference) / (params.albedo_sigma * params.albedo_sigma));
    return normal * depth * albedo;
}

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let centre_guide = unpack_guide(textureLoad(guides, id.xy, 0));
    let centre = textureLoad(source, id.xy, 0);
    var sum = vec3<f32>(0.0);
    var weights = 0.0;
    for (var dy = -2; dy <= 2; dy++) {
        for (var dx = -2; dx <= 2; dx++) {
            let tap = vec2<i32>(id.xy) + vec2<i32>(dx, dy) * i32(params.step);
            if tap.x < 0 || tap.y < 0 || tap.x >= i32(params.width) || tap.y >= i32(params.height) {
                continue;
            }
            let value = textureLoad(source, tap, 0);
            // a tap without samples yet (alpha 0) carries no information
            let weight = B3_SPLINE[abs(dx)] * B3_SPLINE[abs(dy)] * value.w
                * edge_weight(centre_guide, unpack_guide(textureLoad(guides, tap, 0)));
            sum += weight * value.xyz;
            weights += weight;
        }
    }
    textureStore(filtered_out, id.xy, vec4<f32>(select(centre.xyz, sum / weights, weights > 0.0), centre.w));
}
