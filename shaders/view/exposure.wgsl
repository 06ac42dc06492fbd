// Auto-exposure: the resolved image's log-average luminance, smoothed over frames (exposure_state).
//! include "generated/view_structs.wgsl"
//! include "view/tone_curves.wgsl"
//! include "common/finite.wgsl"
//! include "generated/bindings/exposure.wgsl"
//! include "generated/workgroup.wgsl"
//
// One workgroup reads a grid of at most EXPOSURE_GRID x EXPOSURE_GRID pixels spread over the
// image, sums log(max(luminance, LOG_AVERAGE_FLOOR)) (Reinhard et al. 2002's log average) and
// blends the mean into the state: a picture of millions of pixels costs one small dispatch, and
// nothing is read back. The present pass turns the state into a factor (MIDDLE_GREY over exp(x)).

const EXPOSURE_GRID: u32 = 64u;

var<workgroup> partial_sums: array<vec2<f32>, WORKGROUP_X>;

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(local_invocation_index) lane: u32) {
    let size = vec2<u32>(params.width, params.height);
    let grid = min(size, vec2<u32>(EXPOSURE_GRID));
    var sum = vec2<f32>(0.0);
    for (var k = lane; k < grid.x * grid.y; k += WORKGROUP_X) {
        let cell = vec2<u32>(k % grid.x, k / grid.x);
        let pixel = (2u * cell + 1u) * size / (2u * grid);
        let value = textureLoad(image, pixel, 0).xyz;
        // a NaN or infinite pixel is left out of the average
        if is_finite_vec3(value) {
            sum += vec2<f32>(log(max(luminance(max(value, vec3<f32>(0.0))), LOG_AVERAGE_FLOOR)), 1.0);
        }
    }
    partial_sums[lane] = sum;
    for (var half = WORKGROUP_X / 2u; half > 0u; half /= 2u) {
        workgroupBarrier();
        if lane < half {
            partial_sums[lane] += partial_sums[lane + half];
        }
    }
    if lane == 0u {
        let total = partial_sums[0];
        if total.y > 0.0 {
            let measured = total.x / total.y;
            let first = params.restart != 0u || exposure_state[0].y == 0.0;
            let smoothed = select(mix(exposure_state[0].x, measured, params.blend), measured, first);
            exposure_state[0] = vec4<f32>(smoothed, 1.0, 0.0, 0.0);
        }
    }
}
