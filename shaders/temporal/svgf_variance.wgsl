// The variance-guided filter's input: each pixel's demodulated history and the variance of its luminance.
//! include "temporal/svgf_common.wgsl"
//! include "temporal/history_mean.wgsl"
//! include "generated/bindings/svgf_variance.wgsl"
//
// It also writes what the a-trous passes' stops read: the guides' texture and the slopes
// (svgf_filter.py's GUIDE_FORMAT and SLOPE).
//
// A history of SVGF_TEMPORAL_FRAMES frames or more has its own moments (TemporalAccumulation);
// a younger one, whose moments are too few to trust, takes them over its 7x7 neighbourhood
// instead (every other pixel of it), weighted by the geometry, as SVGF does after a disocclusion.

fn illumination(pixel: u32) -> vec3<f32> {
    return history_mean(history[pixel]) / demodulation(gbuffer[pixel].albedo);
}

fn svgf_pass(xy: vec2<i32>, pixel: u32) {
    let here = gbuffer[pixel];
    let gradient = depth_gradient(xy, here);
    textureStore(guides, xy, vec4<f32>(here.normal, select(here.depth, SVGF_SKY_DEPTH, here.surface == SKY_SURFACE)));
    slopes[pixel] = gradient;
    let old = history[pixel];
    var moments = old.moments;
    if old.length < params.temporal_length {
        // the pixel itself (weight 1: the weights never vanish) and every other pixel of the 7x7
        // around it: SVGF's footprint at a third of its loads
        var sums = old.moments;
        var weights = 1.0;
        for (var dy = -3; dy <= 3; dy += 2) {
            for (var dx = -3; dx <= 3; dx += 2) {
                let tap = xy + vec2<i32>(dx, dy);
                let index = clamped_index(tap);
                let expected = dot(gradient, abs(vec2<f32>(f32(dx), f32(dy))));
                let weight = select(0.0, geometry_weight(here, gbuffer[index], expected), inside(tap));
                sums += weight * history[index].moments;
                weights += weight;
            }
        }
        moments = sums / weights;
    }
    let variance = max(moments.y - moments.x * moments.x, 0.0);
    illuminated[pixel] = vec4<f32>(illumination(pixel), variance);
}
