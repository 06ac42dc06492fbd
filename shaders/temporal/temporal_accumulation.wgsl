// Temporal accumulation: this frame's samples added to each pixel's history, reprojected along the G-buffer's motion while anything moves.
//! include "generated/temporal.wgsl"
//! include "integrators/accumulate.wgsl"
//! include "view/tone_curves.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"
//! include "generated/bindings/temporal.wgsl"
//! include "generated/workgroup.wgsl"
//
// The history is a Kahan sum of radiance and its length in samples, so a frame's samples are
// added exactly as the renderer's accumulation adds them (accumulate_sample): while nothing moves
// the history is taken as it is and its mean is the plain mean of every sample since it began.
// While something moves, the history is rebuilt from the previous one at the point each pixel's
// first hit was (bilinear taps that pass the depth, normal and surface tests), demodulated by the
// taps' albedo and remodulated by this pixel's, its length capped at params.length_cap and its
// mean clamped to this frame's neighbourhood (temporal_accumulation.py says why).

// This frame's samples of `pixel`, summed.
fn frame_sum(pixel: u32) -> vec3<f32> {
    let sums = accumulation[pixel];
    return sums.sum.xyz - sums.compensation.xyz;
}

// This frame's mean at `xy`, divided by its first hit's albedo.
fn frame_illumination(xy: vec2<i32>) -> vec3<f32> {
    let pixel = pixel_index(xy);
    return frame_sum(pixel) / (f32(params.samples) * demodulation(gbuffer[pixel].albedo));
}

// How far this pixel's depth may be from a tap's: a little of the distance, plus what the depth
// changes over the taps' pixel of offset in each axis on this surface.
fn depth_tolerance(xy: vec2<i32>, here: GBufferPixel) -> f32 {
    let gradient = depth_gradient(xy, here);
    return DEPTH_RELATIVE_TOLERANCE * here.previous_depth + DEPTH_GRADIENT_MARGIN * (gradient.x + gradient.y);
}

// Whether the previous frame's pixel `there` saw the surface this pixel sees now.
fn consistent(here: GBufferPixel, there: GBufferPixel, tolerance: f32) -> bool {
    if !same_surface(here, there) {
        return false;
    }
    if here.surface == SKY_SURFACE {
        return true;
    }
    return abs(here.previous_depth - there.depth) <= tolerance && dot(here.normal, there.normal) >= NORMAL_COS_MIN;
}

// This frame's demodulated colours over the 3x3 neighbourhood: the box the history is clamped to.
struct ColourBox {
    low: vec3<f32>,
    high: vec3<f32>,
}

fn neighbourhood(xy: vec2<i32>) -> ColourBox {
    var box = ColourBox(vec3<f32>(FLOAT_MAX), vec3<f32>(-FLOAT_MAX));
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let tap = xy + vec2<i32>(dx, dy);
            if inside(tap) {
                let colour = frame_illumination(tap);
                box = ColourBox(min(box.low, colour), max(box.high, colour));
            }
        }
    }
    return box;
}

fn no_history() -> TemporalPixel {
    return TemporalPixel(vec4<f32>(0.0), vec4<f32>(0.0), vec2<f32>(0.0), 0.0);
}

// The previous history where this pixel's first hit was, or none (the pixel starts again) where
// no tap passes.
fn reprojected(xy: vec2<i32>, here: GBufferPixel) -> TemporalPixel {
    // the previous camera did not have the point in front
    if !(here.previous_depth > 0.0) {
        return no_history();
    }
    // pixel centres at integers: the taps are the four around it
    let position = vec2<f32>(xy) + here.motion;
    let corner = floor(position);
    let fraction = position - corner;
    let tolerance = depth_tolerance(xy, here);
    var weights = 0.0;
    var illumination = vec3<f32>(0.0);
    var moments = vec2<f32>(0.0);
    var length = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let offset = vec2<u32>(k & 1u, k >> 1u);
        let tap = vec2<i32>(corner) + vec2<i32>(offset);
        let along = select(1.0 - fraction, fraction, offset == vec2<u32>(1u));
        let weight = along.x * along.y;
        if !(weight >= BILINEAR_WEIGHT_MIN) || !inside(tap) {
            continue;
        }
        let index = pixel_index(tap);
        let there = previous_gbuffer[index];
        let old = previous_history[index];
        if old.length <= 0.0 || !consistent(here, there, tolerance) {
            continue;
        }
        let mean = (old.sum.xyz - old.compensation.xyz) / old.length;
        illumination += weight * mean / demodulation(there.albedo);
        moments += weight * old.moments;
        length += weight * old.length;
        weights += weight;
    }
    if !(weights > 0.0) {
        return no_history();
    }
    let box = neighbourhood(xy);
    let clamped = clamp(illumination / weights, box.low, box.high);
    let kept = min(length / weights, params.length_cap);
    return TemporalPixel(vec4<f32>(clamped * demodulation(here.albedo) * kept, 0.0), vec4<f32>(0.0), moments / weights, kept);
}

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let xy = vec2<i32>(id.xy);
    let pixel = id.y * params.width + id.x;
    var old = no_history();
    if params.reset == 0u && params.moving == 0u {
        old = previous_history[pixel];
    } else if params.reset == 0u {
        old = reprojected(xy, gbuffer[pixel]);
    }
    let samples = f32(params.samples);
    let length = old.length + samples;
    let value = frame_illumination(xy);
    // luminance's first two moments over frames, weighted by their samples: the variance of the
    // demodulated colour for a variance-guided filter
    var brightness = luminance(value);
    brightness = select(0.0, brightness, is_finite_f32(brightness));
    let moments = mix(old.moments, vec2<f32>(brightness, brightness * brightness), samples / length);
    let sum = accumulate_sample(AccumulatedPixel(old.sum, old.compensation), frame_sum(pixel));
    history[pixel] = TemporalPixel(sum.sum, sum.compensation, moments, length);
}
