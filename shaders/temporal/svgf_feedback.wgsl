// SVGF's feedback: the first a-trous pass's illumination, remodulated, becomes the colour of the history the next frame takes.
//! include "temporal/svgf_common.wgsl"
//! include "common/finite.wgsl"
//! include "generated/bindings/svgf_feedback.wgsl"
//
// Run only for frames in motion (VarianceGuidedFilter.filter's `feedback`): the history keeps its
// length and moments, and its sum becomes the filtered mean times that length. The sky passed
// through the filter as it was, and a pixel without history has nothing to replace.

fn svgf_pass(xy: vec2<i32>, pixel: u32) {
    let here = gbuffer[pixel];
    let old = carried[pixel];
    let colour = filtered[pixel].xyz * demodulation(here.albedo) * old.length;
    if here.surface == SKY_SURFACE || !(old.length > 0.0) || !is_finite_vec3(colour) {
        return;
    }
    carried[pixel] = TemporalPixel(vec4<f32>(colour, old.sum.w), vec4<f32>(vec3<f32>(0.0), old.compensation.w), old.moments, old.length);
}
