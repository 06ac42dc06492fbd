// Temporal upsampling: this frame's samples (one pixel of each block) added to the full image's history, reprojected along the traced pixels' motion, and interpolated for pixels without history.
//! include "generated/temporal.wgsl"
//! include "generated/upsampling.wgsl"
//! include "integrators/accumulate.wgsl"
//! include "view/tone_curves.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"
//! include "generated/bindings/upsampling.wgsl"
//! include "generated/workgroup.wgsl"
//
// This frame traced the pixels offset + stride * k (main_subset), one in each stride x stride
// block, each with its own sampler sequence: their accumulation and G-buffer entries are this
// frame's, the others' are stale. Every pixel's history is a Kahan sum of radiance and its length
// in samples, as temporal accumulation's; `surfaces` says what each pixel's history shows (the
// G-buffer of its last sample, or of the history it took), which the next frame's taps are
// tested against. A traced pixel adds its samples to its history; the others keep theirs. While
// nothing moves a history is taken as it is, so a resting camera's pixels are the plain means of
// their samples. While something moves, each pixel takes the previous history where the motion
// vector of a traced pixel near it says its point was, kept where the taps show that pixel's
// surface at the depth expected within their distance (temporal_upsampling.py says why).
// `shown` is the picture as histories: each pixel's, or this frame's samples interpolated as a
// history of one sample where a pixel has none (what the picture and the variance-guided filter read).

fn stride() -> i32 {
    return i32(params.factor);
}

fn subset_offset() -> vec2<i32> {
    return vec2<i32>(i32(params.offset_x), i32(params.offset_y));
}

// The traced pixel nearest to `xy` (ties to the higher one), among this frame's: the image is at
// least a block wide and high, so every block row and column has one inside it.
fn nearest_sample(xy: vec2<i32>) -> vec2<i32> {
    let cell = vec2<f32>(xy - subset_offset()) / f32(stride());
    let last = (vec2<i32>(i32(params.width), i32(params.height)) - 1 - subset_offset()) / stride();
    let k = clamp(vec2<i32>(floor(cell + 0.5)), vec2<i32>(0), last);
    return k * stride() + subset_offset();
}

fn frame_mean(pixel: u32) -> vec3<f32> {
    let sums = accumulation[pixel];
    return (sums.sum.xyz - sums.compensation.xyz) / f32(params.samples);
}

// This frame's mean at the traced pixel `xy`, divided by its first hit's albedo.
fn frame_illumination(xy: vec2<i32>) -> vec3<f32> {
    let pixel = pixel_index(xy);
    return frame_mean(pixel) / demodulation(gbuffer[pixel].albedo);
}

// This frame's samples interpolated at `xy`: bilinear over the four traced pixels around it that
// see the nearest one's surface (the nearest is one of them, of a positive weight).
fn interpolated(xy: vec2<i32>, nearest: GBufferPixel) -> vec3<f32> {
    let cell = vec2<f32>(xy - subset_offset()) / f32(stride());
    let corner = floor(cell);
    let fraction = cell - corner;
    var colour = vec3<f32>(0.0);
    var weights = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let offset = vec2<u32>(k & 1u, k >> 1u);
        let tap = (vec2<i32>(corner) + vec2<i32>(offset)) * stride() + subset_offset();
        let along = select(1.0 - fraction, fraction, offset == vec2<u32>(1u));
        if !inside(tap) || !same_surface(gbuffer[pixel_index(tap)], nearest) {
            continue;
        }
        colour += along.x * along.y * frame_mean(pixel_index(tap));
        weights += along.x * along.y;
    }
    return select(vec3<f32>(0.0), colour / weights, weights > 0.0);
}

// The box of this frame's demodulated samples at the traced pixels around `sample` (itself one).
struct ColourBox {
    low: vec3<f32>,
    high: vec3<f32>,
}

fn neighbourhood(sample: vec2<i32>) -> ColourBox {
    var box = ColourBox(vec3<f32>(FLOAT_MAX), vec3<f32>(-FLOAT_MAX));
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let tap = sample + stride() * vec2<i32>(dx, dy);
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

fn finite_luminance(colour: vec3<f32>) -> f32 {
    let brightness = luminance(colour);
    return select(0.0, brightness, is_finite_f32(brightness));
}

// `colour` as a history of one sample, its moments those of its demodulated luminance.
fn one_sample(colour: vec3<f32>, albedo: vec3<f32>) -> TemporalPixel {
    let brightness = finite_luminance(colour / demodulation(albedo));
    return TemporalPixel(vec4<f32>(colour, 0.0), vec4<f32>(0.0), vec2<f32>(brightness, brightness * brightness), 1.0);
}

// A pixel's history and what it shows.
struct Reprojection {
    history: TemporalPixel,
    shows: GBufferPixel,
}

// Whether the previous frame's history pixel `there` shows the surface `here` expects, its
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

// The previous history's taps that pass for the pixel at `xy` moved along the motion of the traced
// pixel `sample` (G-buffer `here`): their weights, demodulated colour, its luminance moments and
// length (weighted sums), and the heaviest tap's surface.
struct Taps {
    weights: f32,
    illumination: vec3<f32>,
    moments: vec2<f32>,
    length: f32,
    heaviest: GBufferPixel,
}

// The pixel at `xy` expects the sample's surface at the sample's depth, give or take the depth's
// change over the distance between them (none for the sample itself).
fn passing_taps(xy: vec2<i32>, sample: vec2<i32>, here: GBufferPixel) -> Taps {
    var taps = Taps(0.0, vec3<f32>(0.0), vec2<f32>(0.0), 0.0, here);
    // the previous camera did not have the point in front
    if !(here.previous_depth > 0.0) {
        return taps;
    }
    // pixel centres at integers: the taps are the four around it
    let position = vec2<f32>(xy) + here.motion;
    let corner = floor(position);
    let fraction = position - corner;
    let gradient = depth_gradient_over(sample, here, stride());
    let distance = length(vec2<f32>(xy - sample));
    let tolerance = DEPTH_RELATIVE_TOLERANCE * here.previous_depth
        + DEPTH_GRADIENT_MARGIN * (gradient.x + gradient.y) * (1.0 + distance);
    var heaviest = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let offset = vec2<u32>(k & 1u, k >> 1u);
        let tap = vec2<i32>(corner) + vec2<i32>(offset);
        let along = select(1.0 - fraction, fraction, offset == vec2<u32>(1u));
        let weight = along.x * along.y;
        if !(weight >= BILINEAR_WEIGHT_MIN) || !inside(tap) {
            continue;
        }
        let index = pixel_index(tap);
        let there = previous_surfaces[index];
        let old = previous_history[index];
        if old.length <= 0.0 || !consistent(here, there, tolerance) {
            continue;
        }
        let mean = (old.sum.xyz - old.compensation.xyz) / old.length;
        taps.illumination += weight * mean / demodulation(there.albedo);
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

// The previous history where the pixel at `xy` was, or none where no tap passes. A traced pixel
// moves along its own motion; another along that of the nearest of the four traced pixels around
// it (`sample` the nearest) whose surface its history shows there: a pixel beside an edge moves
// with its own side.
fn reprojected(xy: vec2<i32>, sample: vec2<i32>, here: GBufferPixel) -> Reprojection {
    // nearest first: the sample, its neighbour along the axis on which the pixel is farther from
    // it, the other, the diagonal one; a traced pixel is its own sample
    let away = xy - sample;
    let toward = vec2<i32>(select(-1, 1, away.x > 0), select(-1, 1, away.y > 0)) * stride();
    let first_step = select(vec2<i32>(0, toward.y), vec2<i32>(toward.x, 0), abs(away.x) >= abs(away.y));
    let candidates = array<vec2<i32>, 4>(sample, sample + first_step, sample + toward - first_step, sample + toward);
    let count = select(4, 1, all(away == vec2<i32>(0)));
    var source = sample;
    var taps = Taps(0.0, vec3<f32>(0.0), vec2<f32>(0.0), 0.0, here);
    for (var k = 0; k < count; k++) {
        let candidate = candidates[k];
        if !inside(candidate) {
            continue;
        }
        taps = passing_taps(xy, candidate, gbuffer[pixel_index(candidate)]);
        if taps.weights > 0.0 {
            source = candidate;
            break;
        }
    }
    let moved = gbuffer[pixel_index(source)];
    if !(taps.weights > 0.0) {
        return Reprojection(no_history(), here);
    }
    let box = neighbourhood(source);
    let clamped = clamp(taps.illumination / taps.weights, box.low, box.high);
    let kept = min(taps.length / taps.weights, params.length_cap);
    // a traced pixel knows its own albedo; another takes its heaviest tap's, which keeps textures
    // as sharp as the nearest history
    let best = taps.heaviest;
    let albedo = select(best.albedo, here.albedo, all(xy == sample));
    let history = TemporalPixel(vec4<f32>(clamped * demodulation(albedo) * kept, 0.0), vec4<f32>(0.0), taps.moments / taps.weights, kept);
    // its point's distance from this camera: the tap's, changed as the source's changed (a traced
    // pixel shows its own G-buffer instead: main)
    let depth = best.depth + moved.depth - moved.previous_depth;
    return Reprojection(history, GBufferPixel(best.normal, depth, albedo, moved.surface, vec2<f32>(0.0), 0.0, moved.object));
}

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let xy = vec2<i32>(id.xy);
    let pixel = id.y * params.width + id.x;
    let sample = nearest_sample(xy);
    let here = gbuffer[pixel_index(sample)];
    var kept = Reprojection(no_history(), here);
    if params.reset == 0u && params.moving == 0u {
        kept = Reprojection(previous_history[pixel], previous_surfaces[pixel]);
    } else if params.reset == 0u {
        kept = reprojected(xy, sample, here);
    }
    if any(xy != sample) {
        history[pixel] = kept.history;
        surfaces[pixel] = kept.shows;
        if kept.history.length > 0.0 {
            shown[pixel] = kept.history;
        } else {
            shown[pixel] = one_sample(interpolated(xy, here), here.albedo);
        }
        return;
    }
    let old = kept.history;
    let samples = f32(params.samples);
    let length = old.length + samples;
    // luminance's first two moments over frames, weighted by their samples (as temporal
    // accumulation keeps them): the variance-guided filter's
    let brightness = finite_luminance(frame_illumination(xy));
    let moments = mix(old.moments, vec2<f32>(brightness, brightness * brightness), samples / length);
    let sums = accumulation[pixel];
    let sum = accumulate_sample(AccumulatedPixel(old.sum, old.compensation), sums.sum.xyz - sums.compensation.xyz);
    let updated = TemporalPixel(sum.sum, sum.compensation, moments, length);
    history[pixel] = updated;
    shown[pixel] = updated;
    surfaces[pixel] = here;
}
