// One a-trous pass of the variance-guided filter (SVGF) on demodulated illumination and its variance.
//! include "temporal/svgf_common.wgsl"
//! include "generated/bindings/svgf_atrous.wgsl"
//
// Pass k spreads the 5x5 B3-spline kernel 2^k pixels apart. Taps are weighted down across depth
// and normal edges and across luminance differences large against the noise: the standard
// deviation from the variance, blurred over 3x3 first (Schied et al. 2017). The stops read the
// guides the variance pass wrote, the depth and luminance stops one exp2 of their exponents'
// sum. The variance is filtered with the squared weights, so each pass's luminance stop trusts the
// last's result more. The last pass at full resolution multiplies the albedo back (params.last;
// at half resolution svgf_upsample.wgsl does). The sky passes
// through: seen directly it carries no path's noise, and filtering would only blur the environment
// map and mix in the pixels at its edge; a tap on the sky weighs 0.

const B3_SPLINE = array<f32, 3>(0.375, 0.25, 0.0625);
const GAUSSIAN_3X3 = array<f32, 2>(0.25, 0.125);

fn blurred_variance(xy: vec2<i32>) -> f32 {
    var sum = 0.0;
    var weights = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let tap = xy + vec2<i32>(dx, dy);
            let kernel = GAUSSIAN_3X3[abs(dx)] * GAUSSIAN_3X3[abs(dy)] * select(1.0, 2.0, dx == 0 && dy == 0);
            let weight = select(0.0, kernel, inside(tap));
            sum += weight * source[clamped_index(tap)].w;
            weights += weight;
        }
    }
    return sum / weights;
}

fn svgf_pass(xy: vec2<i32>, pixel: u32) {
    let here = textureLoad(guides, xy, 0);
    let centre = source[pixel];
    if here.w == SVGF_SKY_DEPTH {
        filtered_out[pixel] = remodulated(centre, pixel);
        return;
    }
    let gradient = slopes[pixel];
    let brightness = luminance(centre.xyz);
    // the luminance stop's exponent per unit of luminance; SVGF_SPREAD_MIN keeps a noiseless
    // pixel's from 0 / 0
    let luminance_scale = -LOG2_E / (params.luminance_sigma * sqrt(blurred_variance(xy)) + SVGF_SPREAD_MIN);
    var colour = vec3<f32>(0.0);
    var variance = 0.0;
    var weights = 0.0;
    for (var dy = -2; dy <= 2; dy++) {
        for (var dx = -2; dx <= 2; dx++) {
            let offset = vec2<i32>(dx, dy) * i32(params.step);
            let tap = xy + offset;
            let nearest = clamped(tap);
            let there = textureLoad(guides, nearest, 0);
            let value = source[pixel_index(nearest)];
            let exponent = depth_stop_log2(here.w, there.w, dot(gradient, abs(vec2<f32>(offset))))
                + luminance_scale * abs(luminance(value.xyz) - brightness);
            let stops = exp2(exponent) * normal_stop(here.xyz, there.xyz);
            let kept = inside(tap) && there.w != SVGF_SKY_DEPTH;
            let weight = select(0.0, B3_SPLINE[abs(dx)] * B3_SPLINE[abs(dy)] * stops, kept);
            colour += weight * value.xyz;
            variance += weight * weight * value.w;
            weights += weight;
        }
    }
    // the centre tap's weight is B3(0)^2 > 0: weights never vanish
    filtered_out[pixel] = remodulated(vec4<f32>(colour / weights, variance / (weights * weights)), pixel);
}
