// The path tracer over a band of rows: one sample for each pixel of rows [first_row, first_row + rows).
//! include "integrators/path_tracer.wgsl"
//
// A whole pass over a large image takes seconds on a CPU adapter; the viewer splits it into
// bands sized to its frame-time budget so the window keeps answering between bands.

// The first row of this dispatch's band: band_first_row (BAND_GROUP).
//! include "generated/bindings/band.wgsl"

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main_rows(@builtin(global_invocation_id) id: vec3<u32>) {
    render_pixel(vec2<u32>(id.x, id.y + band_first_row), 1u);
}
