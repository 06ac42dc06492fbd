// Temporal upsampling: this frame's samples (one pixel of each block) added to the full image's history, reprojected along the traced pixels' motion, and interpolated over the pixels not traced.
//! include "temporal/history.wgsl"
//! include "temporal/traced_pixels.wgsl"
//! include "generated/bindings/upsampling.wgsl"
//
// This frame traced the pixels offset + stride * k (main_subset), one in each stride x stride
// block, each with its own sampler sequence: their accumulation and G-buffer entries are this
// frame's, the others' are stale. Every pixel's history is a Kahan sum of radiance and its length
// in samples, as temporal accumulation's; `surfaces` says what each pixel's history shows (the
// G-buffer of its last sample, or of the history it took), which the next frame's taps are
// tested against. A traced pixel adds its samples to its history; at rest the others keep theirs,
// so a resting camera's pixels are the plain means of their samples. While something moves, each
// pixel takes the previous history where the motion vector of a traced pixel near it says its
// point was, kept where the taps show that pixel's surface at the depth expected within their
// distance, and a pixel not traced adds this frame's samples interpolated over it as a part of a
// sample (temporal_upsampling.py says why). `shown` is the picture as histories: each pixel's, or
// this frame's samples interpolated where a pixel has none (what the picture and the
// variance-guided filter read).

// The traced pixel nearest to `xy` (ties to the higher one), among this frame's: the image is at
// least a block wide and high, so every block row and column has one inside it.
fn nearest_sample(xy: vec2<i32>) -> vec2<i32> {
    let cell = vec2<f32>(xy - subset_offset()) / f32(stride());
    let last = (vec2<i32>(i32(params.width), i32(params.height)) - 1 - subset_offset()) / stride();
    let k = clamp(vec2<i32>(floor(cell + 0.5)), vec2<i32>(0), last);
    return traced_pixel(k);
}

fn frame_mean(pixel: u32) -> vec3<f32> {
    return frame_sum(pixel) / f32(params.samples);
}

// This frame's demodulated samples interpolated at `xy` (rgb) and their weight (w, 0 for none):
// bilinear over the four traced pixels around it that see `surface`, facing as it faces (not
// across a crease of one object; the nearest traced pixel's surface is one of them, of a positive
// weight).
fn interpolated(xy: vec2<i32>, surface: GBufferPixel) -> vec4<f32> {
    let cell = vec2<f32>(xy - subset_offset()) / f32(stride());
    let corner = floor(cell);
    let fraction = cell - corner;
    var colour = vec3<f32>(0.0);
    var weights = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let bilinear = bilinear_tap(fraction, k);
        let tap = traced_pixel(vec2<i32>(corner) + bilinear.offset);
        if !inside(tap) {
            continue;
        }
        let there = gbuffer[pixel_index(tap)];
        if !same_surface(there, surface) || dot(there.normal, surface.normal) < NORMAL_COS_MIN {
            continue;
        }
        colour += bilinear.weight * frame_mean(pixel_index(tap)) / demodulation(there.albedo);
        weights += bilinear.weight;
    }
    return select(vec4<f32>(0.0), vec4<f32>(colour / weights, weights), weights > 0.0);
}

// `old` with this frame's interpolated samples (`illumination`, demodulated, for a pixel whose
// history shows `albedo`) added as INTERPOLATED_SAMPLE_WEIGHT of each sample the frame took: a
// pixel traced once every factor x factor frames gains every frame what its neighbours saw.
fn with_interpolated(old: TemporalPixel, illumination: vec3<f32>, albedo: vec3<f32>) -> TemporalPixel {
    let weight = INTERPOLATED_SAMPLE_WEIGHT * f32(params.samples);
    return with_samples(old, weight * illumination * demodulation(albedo), illumination, weight);
}

// The previous history where the pixel at `xy` was, or none where no tap passes. A traced pixel
// moves along its own motion; another along that of the nearest of the four traced pixels around
// it (`here` the nearest's G-buffer) whose surface its history shows there: a pixel beside an edge
// moves with its own side.
fn reprojected(xy: vec2<i32>, here: GBufferPixel) -> Reprojection {
    let sample = nearest_sample(xy);
    // nearest first: the sample, its neighbour along the axis on which the pixel is farther from
    // it, the other, the diagonal one; a traced pixel is its own sample
    let away = xy - sample;
    let toward = vec2<i32>(select(-1, 1, away.x > 0), select(-1, 1, away.y > 0)) * stride();
    let first_step = select(vec2<i32>(0, toward.y), vec2<i32>(toward.x, 0), abs(away.x) >= abs(away.y));
    let candidates = array<vec2<i32>, 4>(sample, sample + first_step, sample + toward - first_step, sample + toward);
    let count = select(4, 1, all(away == vec2<i32>(0)));
    // the candidate whose motion the history is taken along: its G-buffer and neighbourhood
    var moved = here;
    var around: TracedNeighbourhood;
    var taps = no_taps(here);
    for (var k = 0; k < count; k++) {
        let candidate = candidates[k];
        if !inside(candidate) {
            continue;
        }
        // the pixel expects the candidate's surface at its depth, give or take the depth's change
        // over the distance between them (none for the traced pixel itself)
        moved = gbuffer[pixel_index(candidate)];
        around = traced[traced_index(candidate)];
        let gradient = vec2<f32>(around.gradient_x, around.gradient_y);
        taps = passing_taps(xy, moved, depth_tolerance(moved, gradient, length(vec2<f32>(xy - candidate))));
        if taps.weights > 0.0 {
            break;
        }
    }
    if !(taps.weights > 0.0) {
        return Reprojection(no_history(), here);
    }
    // a traced pixel knows its own albedo; another takes its heaviest tap's, which keeps textures
    // as sharp as the nearest history
    let best = taps.heaviest;
    let albedo = select(best.albedo, here.albedo, all(xy == sample));
    let history = reprojected_history(taps, ColourBox(around.low, around.high), albedo);
    // its point's distance from this camera: the tap's, changed as `moved`'s changed (a traced
    // pixel shows its own G-buffer instead: history_pass); its motion and distance from the previous
    // camera, `moved`'s, whose motion the history was taken along (what temporal antialiasing
    // follows)
    let depth = best.depth + moved.depth - moved.previous_depth;
    return Reprojection(history, GBufferPixel(best.normal, depth, albedo, moved.surface, moved.motion, moved.previous_depth, moved.object));
}

fn history_pass(xy: vec2<i32>, pixel: u32) {
    let sample = nearest_sample(xy);
    let here = gbuffer[pixel_index(sample)];
    let kept = previous(xy, here);
    if all(xy == sample) {
        let updated = with_frame(kept.history, xy);
        history[pixel] = updated;
        shown[pixel] = updated;
        surfaces[pixel] = here;
        return;
    }
    // at rest a pixel's history holds its own samples alone (render()'s mean); while anything
    // moves, and where a pixel has no history, it takes this frame's samples of the surface its
    // history shows too
    var updated = kept.history;
    // a pixel without history shows what the traced pixel nearest it sees
    var shows = kept.shows;
    if !(updated.length > 0.0) {
        shows = here;
    }
    if params.moving != 0u || !(updated.length > 0.0) {
        let around = interpolated(xy, shows);
        if around.w > 0.0 {
            updated = with_interpolated(updated, around.xyz, shows.albedo);
        }
    }
    shown[pixel] = updated;
    if params.moving != 0u {
        history[pixel] = updated;
    } else {
        history[pixel] = kept.history;
    }
    surfaces[pixel] = shows;
}
