// The edges of BVH boxes drawn over the picture as lines, projected by the path tracer's camera.
//! include "generated/view_structs.wgsl"
//! include "generated/display_constants.wgsl"
//! include "generated/bindings/box_lines.wgsl"
//
// The projection maps a point to the pixel its camera ray passes through (see BoxLinesParams),
// so the lines sit exactly on the traced geometry; the GPU clips what lies behind the camera.

@vertex
fn vertex_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let point = vec4<f32>(endpoints[index].xyz, 1.0);
    return vec4<f32>(dot(params.row_x, point), dot(params.row_y, point), dot(params.row_z, point), dot(params.row_w, point));
}

@fragment
fn fragment_main() -> @location(0) vec4<f32> {
    return params.color;
}
