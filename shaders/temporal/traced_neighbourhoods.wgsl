// What the rebuilding of an upsampled picture reads of each traced pixel, written once a frame before it: the box about this frame's colours around the pixel, and its surface's depth gradient.
//! include "temporal/frame_colours.wgsl"
//! include "temporal/traced_pixels.wgsl"
//! include "generated/workgroup.wgsl"
//! include "generated/bindings/upsampling.wgsl"
//
// Every pixel of the image moves its history along one of the traced pixels around it and clamps
// it to that pixel's box (temporal_upsampling.wgsl): computed here once per traced pixel instead of
// once per pixel, f x f times fewer. One invocation per block, as the frame traced them.

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let xy = traced_pixel(vec2<i32>(id.xy));
    if !inside(xy) {
        return;
    }
    let here = gbuffer[pixel_index(xy)];
    let box = neighbourhood(xy, stride());
    let gradient = depth_gradient_over(xy, here, stride());
    traced[traced_index(xy)] = TracedNeighbourhood(box.low, gradient.x, box.high, gradient.y);
}
