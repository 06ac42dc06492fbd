// Temporal antialiasing of the upsampled picture: the filtered picture blended with the last frame's output, taken along each pixel's motion and clamped to this frame's neighbourhood.
//! include "generated/antialiasing.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"
//! include "common/finite.wgsl"
//! include "generated/workgroup.wgsl"
//! include "generated/bindings/antialiasing.wgsl"
//
// `current` is this frame's filtered picture (rgb, and the variance in w, passed on as it is),
// `previous_output` what this pass wrote the frame before, `gbuffer` what each pixel shows (its
// motion to where the previous camera saw it, and whether it did: previous_depth > 0). While
// nothing moves, after a restart and where the previous camera did not see the point, a pixel is
// this frame's picture alone (temporal_antialiasing.py says why).

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let xy = vec2<i32>(id.xy);
    if inside(xy) {
        let pixel = pixel_index(xy);
        output[pixel] = antialiased(xy, pixel);
    }
}

// The last frame's output where the pixel at `xy` was, moved along `motion`: bilinear over the
// taps inside the image (rgb), and their weight (w, 0 for none).
fn previous_output_at(xy: vec2<i32>, motion: vec2<f32>) -> vec4<f32> {
    // pixel centres at integers: the taps are the four around it
    let position = vec2<f32>(xy) + motion;
    let corner = floor(position);
    let fraction = position - corner;
    var colour = vec3<f32>(0.0);
    var weights = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let bilinear = bilinear_tap(fraction, k);
        let tap = vec2<i32>(corner) + bilinear.offset;
        if inside(tap) {
            colour += bilinear.weight * previous_output[pixel_index(tap)].xyz;
            weights += bilinear.weight;
        }
    }
    return vec4<f32>(colour, weights);
}

// The smallest and largest of this frame's picture over the 3x3 pixels around `centre`, per channel.
struct Bounds {
    low: vec3<f32>,
    high: vec3<f32>,
}

fn neighbourhood_bounds(centre: vec2<i32>) -> Bounds {
    var bounds = Bounds(vec3<f32>(FLOAT_MAX), vec3<f32>(-FLOAT_MAX));
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let tap = centre + vec2<i32>(dx, dy);
            if inside(tap) {
                let colour = current[pixel_index(tap)].xyz;
                bounds = Bounds(min(bounds.low, colour), max(bounds.high, colour));
            }
        }
    }
    return bounds;
}

fn antialiased(xy: vec2<i32>, pixel: u32) -> vec4<f32> {
    let now = current[pixel];
    let here = gbuffer[pixel];
    if params.moving == 0u || !(here.previous_depth > 0.0) {
        return now;
    }
    let before = previous_output_at(xy, here.motion);
    if !(before.w > 0.0) {
        return now;
    }
    let bounds = neighbourhood_bounds(xy);
    let kept = clamp(before.xyz / before.w, bounds.low, bounds.high);
    let blended = mix(kept, now.xyz, ANTIALIASING_BLEND);
    return select(now, vec4<f32>(blended, now.w), is_finite_vec3(blended));
}
