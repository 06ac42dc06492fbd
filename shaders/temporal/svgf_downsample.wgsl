// The variance-guided filter's input at half resolution, for upsampled pictures: each 2 x 2 block's illumination, variance and guides.
//! include "temporal/svgf_common.wgsl"
//! include "generated/bindings/svgf_downsample.wgsl"
//
// Run over the half-resolution image with params of the full one. A block stands at its top-left
// pixel: its guides, and its depth slopes per half-resolution pixel (twice the full one's). Its
// illumination and variance are the means over the block's pixels weighted by how much each says
// about the top-left one (geometry_weight: nothing across the sky's edge, little across a crease or
// a depth step), the variance's mean and not the mean's: an upsampled picture's neighbouring pixels
// share samples, so their noise does not average down.

fn svgf_pass(xy: vec2<i32>, pixel: u32) {
    if any(xy >= half_size()) {
        return;
    }
    let corner = 2 * xy;
    let here = gbuffer[pixel_index(corner)];
    let gradient = slopes[pixel_index(corner)];
    var sum = vec4<f32>(0.0);
    var weights = 0.0;
    for (var k = 0; k < 4; k++) {
        let offset = vec2<i32>(k & 1, k >> 1);
        let tap = corner + offset;
        let index = clamped_index(tap);
        let expected = dot(gradient, vec2<f32>(offset));
        let weight = select(0.0, geometry_weight(here, gbuffer[index], expected), inside(tap));
        sum += weight * illuminated[index];
        weights += weight;
    }
    // the top-left pixel weighs 1: weights never vanish
    let block = half_index(xy);
    reduced[block] = sum / weights;
    textureStore(half_guides, xy, textureLoad(guides, corner, 0));
    half_slopes[block] = HALF_RESOLUTION_SLOPE_SCALE * gradient;
}
