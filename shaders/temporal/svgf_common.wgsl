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

// The guides' depth (svgf_filter.py's GUIDE_FORMAT) where the sky was seen: no surface's distance
// is negative.
const SVGF_SKY_DEPTH: f32 = -1.0;

// The pixel in the image nearest `tap`: taps beyond the edge read it and weigh 0, rather than
// branching away (lavapipe runs a workgroup's pixels in lockstep, and a branch splits them).
fn clamped(tap: vec2<i32>) -> vec2<i32> {
    return clamp(tap, vec2<i32>(0), vec2<i32>(i32(params.width), i32(params.height)) - 1);
}

fn clamped_index(tap: vec2<i32>) -> u32 {
    return pixel_index(clamped(tap));
}

// `filtered` (demodulated illumination, variance) as the pass at `pixel` writes it: times the
// pixel's albedo where the pass is the last (params.last), as it is otherwise.
fn remodulated(filtered: vec4<f32>, pixel: u32) -> vec4<f32> {
    if params.last == 0u {
        return filtered;
    }
    return vec4<f32>(filtered.xyz * demodulation(gbuffer[pixel].albedo), filtered.w);
}

// The size of the half-resolution image a full one of params.width x params.height reduces to
// (svgf_downsample.wgsl): a pixel per 2 x 2 block, the blocks cut by the edge included.
fn half_size() -> vec2<i32> {
    return (vec2<i32>(i32(params.width), i32(params.height)) + 1) / 2;
}

fn half_index(xy: vec2<i32>) -> u32 {
    return u32(xy.y * half_size().x + xy.x);
}

// log2(e): the stops are exp2 of their exponents times it (lavapipe's exp is exp2 of a product anyway).
const LOG2_E: f32 = 1.4426950408889634;

// Schied et al.'s normal stop: the cosine between the normals to the SVGF_NORMAL_POWER, by
// SVGF_NORMAL_SQUARINGS squarings (pow would cost an exp2 and a log2 per tap).
fn normal_stop(here: vec3<f32>, there: vec3<f32>) -> f32 {
    var stop = max(dot(here, there), 0.0);
    for (var k = 0u; k < SVGF_NORMAL_SQUARINGS; k++) {
        stop *= stop;
    }
    return stop;
}

// The base-2 exponent of Schied et al.'s depth stop between depths `here` and `there`, where the
// depth of `here`'s surface would change by `expected` between them (SVGF_DEPTH_FLOOR of the
// distance keeps a surface facing the camera from stopping at rounding).
fn depth_stop_log2(here: f32, there: f32, expected: f32) -> f32 {
    return -abs(here - there) * LOG2_E / (SVGF_DEPTH_SIGMA * expected + SVGF_DEPTH_FLOOR * here);
}

// How much a tap that hit `there` says about the pixel that hit `here`, where the depth of
// `here`'s surface would change by `expected` between them: nothing across the sky's edge, less
// across depth steps beyond the slope and across normals.
fn geometry_weight(here: GBufferPixel, there: GBufferPixel, expected: f32) -> f32 {
    if (here.surface == SKY_SURFACE) != (there.surface == SKY_SURFACE) {
        return 0.0;
    }
    if here.surface == SKY_SURFACE {
        return 1.0;
    }
    return exp2(depth_stop_log2(here.depth, there.depth, expected)) * normal_stop(here.normal, there.normal);
}
