// The variance-guided filter's half-resolution result brought back to full resolution (joint bilateral upsampling), remodulated where it is the last pass.
//! include "temporal/svgf_common.wgsl"
//! include "generated/bindings/svgf_upsample.wgsl"
//
// Each pixel takes the bilinear taps of the half-resolution result around it (svgf_downsample.wgsl's
// blocks, each standing at its top-left pixel), weighted down across depth and normal edges as the
// a-trous passes weigh theirs, so that an edge stays where the full-resolution guides put it. A
// pixel none of whose taps sees its surface (a feature thinner than a block) keeps its own
// unfiltered illumination (`own`), as does the sky.

fn svgf_pass(xy: vec2<i32>, pixel: u32) {
    let here = textureLoad(guides, xy, 0);
    let mine = own[pixel];
    if here.w == SVGF_SKY_DEPTH {
        filtered_out[pixel] = remodulated(mine, pixel);
        return;
    }
    // pixel centres at integers: the full pixel xy is at (xy - 0.5) / 2 among the half ones
    let position = (vec2<f32>(xy) - 0.5) * 0.5;
    let corner = vec2<i32>(floor(position));
    let fraction = position - floor(position);
    let gradient = slopes[pixel];
    let last = half_size() - 1;
    var colour = vec4<f32>(0.0);
    var weights = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let bilinear = bilinear_tap(fraction, k);
        let tap = clamp(corner + bilinear.offset, vec2<i32>(0), last);
        let there = textureLoad(half_guides, tap, 0);
        let distance = abs(vec2<f32>(2 * tap - xy));
        let stops = exp2(depth_stop_log2(here.w, there.w, dot(gradient, distance))) * normal_stop(here.xyz, there.xyz);
        let weight = select(0.0, bilinear.weight * stops, there.w != SVGF_SKY_DEPTH);
        colour += weight * source[half_index(tap)];
        weights += weight;
    }
    let filtered = select(mine, colour / weights, weights > UPSAMPLE_WEIGHT_MIN);
    filtered_out[pixel] = remodulated(filtered, pixel);
}
