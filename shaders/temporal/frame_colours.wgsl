// This frame's demodulated colours: a pixel's, and the box a moving history is clamped to about those around it.
//! include "generated/temporal.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"
//
// The including kernel binds `params` (with the image's size and `samples` per pixel this frame),
// `accumulation` (this frame's sums) and `gbuffer` (this frame's).

fn frame_sum(pixel: u32) -> vec3<f32> {
    let sums = accumulation[pixel];
    return sums.sum.xyz - sums.compensation.xyz;
}

// This frame's mean at `xy`, divided by its first hit's albedo.
fn frame_illumination(xy: vec2<i32>) -> vec3<f32> {
    let pixel = pixel_index(xy);
    return frame_sum(pixel) / (f32(params.samples) * demodulation(gbuffer[pixel].albedo));
}

// The box a reprojected history is clamped to: this frame's demodulated colours at the pixels
// `spacing` apart around `centre` (itself one), their mean give or take COLOUR_BOX_SIGMAS standard
// deviations (variance clipping, Salvi 2016). Not their min and max: with a sample or so per pixel
// the true mean of a noisy, skewed neighbourhood (light through glass, a caustic) lies above the
// brightest of its nine samples more often than not, and a min-max box darkens it.
struct ColourBox {
    low: vec3<f32>,
    high: vec3<f32>,
}

fn neighbourhood(centre: vec2<i32>, spacing: i32) -> ColourBox {
    var sum = vec3<f32>(0.0);
    var squares = vec3<f32>(0.0);
    var count = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let tap = centre + spacing * vec2<i32>(dx, dy);
            if inside(tap) {
                let colour = frame_illumination(tap);
                sum += colour;
                squares += colour * colour;
                count += 1.0;
            }
        }
    }
    // the centre is inside: count >= 1
    let mean = sum / count;
    let spread = COLOUR_BOX_SIGMAS * sqrt(max(squares / count - mean * mean, vec3<f32>(0.0)));
    return ColourBox(mean - spread, mean + spread);
}
