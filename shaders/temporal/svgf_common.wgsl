// What the variance-guided filter's passes share: the entry point over the image and the G-buffer's edge stops.
//! include "generated/svgf.wgsl"
//! include "view/tone_curves.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"
//! include "generated/workgroup.wgsl"
//
// Each pass's file defines `svgf_pass(xy, pixel)`, which main runs for every pixel of the image
// (the last workgroups overhang it).

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let xy = vec2<i32>(id.xy);
    if inside(xy) {
        svgf_pass(xy, pixel_index(xy));
    }
}

// How much a tap that hit `there` says about the pixel that hit `here`, where the depth of
// `here`'s surface would change by `expected` between them: nothing across the sky's edge, less
// across depth steps beyond the slope and across normals (Schied et al.'s depth and normal stops;
// SVGF_DEPTH_FLOOR of the distance keeps a surface facing the camera from stopping at rounding).
fn geometry_weight(here: GBufferPixel, there: GBufferPixel, expected: f32) -> f32 {
    if (here.surface == SKY_SURFACE) != (there.surface == SKY_SURFACE) {
        return 0.0;
    }
    if here.surface == SKY_SURFACE {
        return 1.0;
    }
    let depth = exp(-abs(here.depth - there.depth) / (SVGF_DEPTH_SIGMA * expected + SVGF_DEPTH_FLOOR * here.depth));
    let normal = pow(max(dot(here.normal, there.normal), 0.0), SVGF_NORMAL_POWER);
    return depth * normal;
}
