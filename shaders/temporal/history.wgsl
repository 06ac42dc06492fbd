// A pixel's history as the temporal passes keep it: this frame's samples added, the previous history reprojected through bilinear taps that see the same surface, clamped to a box about this frame's colours.
//! include "generated/temporal.wgsl"
//! include "integrators/accumulate.wgsl"
//! include "view/tone_curves.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"
//! include "temporal/frame_colours.wgsl"
//! include "temporal/history_mean.wgsl"
//! include "generated/workgroup.wgsl"
//
// The including kernel binds `params` (the image's size, `samples` per pixel this frame, whether
// anything `moving`, whether to `reset` every history, the history's `length_cap`), `accumulation`
// (this frame's sums), `gbuffer` (this frame's), `previous_history` and `previous_surfaces` (what
// each pixel of the previous history shows), and defines `reprojected(xy, here)` and
// `history_pass(xy, pixel)`, which main runs for every pixel of the image (the last workgroups
// overhang it).

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let xy = vec2<i32>(id.xy);
    if inside(xy) {
        history_pass(xy, pixel_index(xy));
    }
}

// The first two moments of `illumination`'s luminance (0 where it is not finite): what a
// history's moments average over its samples.
fn luminance_moments(illumination: vec3<f32>) -> vec2<f32> {
    var brightness = luminance(illumination);
    brightness = select(0.0, brightness, is_finite_f32(brightness));
    return vec2<f32>(brightness, brightness * brightness);
}

fn no_history() -> TemporalPixel {
    return TemporalPixel(vec4<f32>(0.0), vec4<f32>(0.0), vec2<f32>(0.0), 0.0);
}

// `old` with `weight` samples more, of radiance summing to `total` and demodulated colour
// `illumination`, added as the renderer's accumulation adds them (accumulate_sample), and its
// luminance's first two moments over frames, weighted by their samples: the variance of the
// demodulated colour for the variance-guided filter.
fn with_samples(old: TemporalPixel, total: vec3<f32>, illumination: vec3<f32>, weight: f32) -> TemporalPixel {
    let length = old.length + weight;
    let moments = mix(old.moments, luminance_moments(illumination), weight / length);
    let sum = accumulate_sample(AccumulatedPixel(old.sum, old.compensation), total);
    return TemporalPixel(sum.sum, sum.compensation, moments, length);
}

// `old` with this frame's samples at `xy` added (with_samples).
fn with_frame(old: TemporalPixel, xy: vec2<i32>) -> TemporalPixel {
    return with_samples(old, frame_sum(pixel_index(xy)), frame_illumination(xy), f32(params.samples));
}

// How far the depth from the previous camera of `here` (a pixel's G-buffer, or the G-buffer of a
// traced pixel `distance` pixels from the one reprojected) may be from a tap's: a little of the
// distance, plus what the depth changes over the taps' pixel of offset in each axis on this
// surface (`gradient`, per pixel: depth_gradient_over), times one plus that distance.
fn depth_tolerance(here: GBufferPixel, gradient: vec2<f32>, distance: f32) -> f32 {
    return DEPTH_RELATIVE_TOLERANCE * here.previous_depth
        + DEPTH_GRADIENT_MARGIN * (gradient.x + gradient.y) * (1.0 + distance);
}

// Whether the previous history's pixel showing `there` shows the surface `here` expects, its
// depth from the previous camera within `tolerance` of here's.
fn consistent(here: GBufferPixel, there: GBufferPixel, tolerance: f32) -> bool {
    if !same_surface(here, there) {
        return false;
    }
    if here.surface == SKY_SURFACE {
        return true;
    }
    return abs(here.previous_depth - there.depth) <= tolerance && dot(here.normal, there.normal) >= NORMAL_COS_MIN;
}

// The previous history's taps that pass: their weights, demodulated colour, its luminance moments
// and length (weighted sums), and the heaviest tap's surface.
struct Taps {
    weights: f32,
    illumination: vec3<f32>,
    moments: vec2<f32>,
    length: f32,
    heaviest: GBufferPixel,
}

// No tap (of a pixel that sees `here`).
fn no_taps(here: GBufferPixel) -> Taps {
    return Taps(0.0, vec3<f32>(0.0), vec2<f32>(0.0), 0.0, here);
}

// The bilinear taps of the previous history where the pixel at `xy` was, moved along the motion
// of `here` (a G-buffer entry), that show here's surface within `tolerance` (consistent).
fn passing_taps(xy: vec2<i32>, here: GBufferPixel, tolerance: f32) -> Taps {
    var taps = no_taps(here);
    // the previous camera did not have the point in front
    if !(here.previous_depth > 0.0) {
        return taps;
    }
    // pixel centres at integers: the taps are the four around it
    let position = vec2<f32>(xy) + here.motion;
    let corner = floor(position);
    let fraction = position - corner;
    var heaviest = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let bilinear = bilinear_tap(fraction, k);
        let tap = vec2<i32>(corner) + bilinear.offset;
        let weight = bilinear.weight;
        if !(weight >= BILINEAR_WEIGHT_MIN) || !inside(tap) {
            continue;
        }
        let index = pixel_index(tap);
        let there = previous_surfaces[index];
        let old = previous_history[index];
        if old.length <= 0.0 || !consistent(here, there, tolerance) {
            continue;
        }
        taps.illumination += weight * history_mean(old) / demodulation(there.albedo);
        taps.moments += weight * old.moments;
        taps.length += weight * old.length;
        taps.weights += weight;
        if weight > heaviest {
            heaviest = weight;
            taps.heaviest = there;
        }
    }
    return taps;
}

// The history `taps` (some passed) make: their mean clamped to `box` widened by COLOUR_BOX_SIGMAS
// of the history's own standard deviation (its luminance moments: a history that has seen rare
// bright samples keeps its mean where this frame's few samples missed them), remodulated by
// `albedo`, its length capped at params.length_cap.
fn reprojected_history(taps: Taps, box: ColourBox, albedo: vec3<f32>) -> TemporalPixel {
    let moments = taps.moments / taps.weights;
    let own = COLOUR_BOX_SIGMAS * sqrt(max(moments.y - moments.x * moments.x, 0.0));
    let clamped = clamp(taps.illumination / taps.weights, box.low - own, box.high + own);
    let kept = min(taps.length / taps.weights, params.length_cap);
    return TemporalPixel(vec4<f32>(clamped * demodulation(albedo) * kept, 0.0), vec4<f32>(0.0), moments, kept);
}

// A pixel's history and what it shows: the G-buffer entry the next frame's taps are tested against.
struct Reprojection {
    history: TemporalPixel,
    shows: GBufferPixel,
}

// The previous history as this frame takes it at the pixel at `xy`, which sees the surface `here`:
// none on the first frame and after a restart, the pixel's own while nothing moves, else where
// the including kernel's `reprojected` finds it.
fn previous(xy: vec2<i32>, here: GBufferPixel) -> Reprojection {
    let pixel = pixel_index(xy);
    if params.reset != 0u {
        return Reprojection(no_history(), here);
    }
    if params.moving == 0u {
        return Reprojection(previous_history[pixel], previous_surfaces[pixel]);
    }
    return reprojected(xy, here);
}
