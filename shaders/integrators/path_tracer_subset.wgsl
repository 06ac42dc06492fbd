// The path tracer over a subset of pixels: `samples_this_dispatch` samples of one pixel in each square block of the image (temporal upsampling).
//! include "integrators/path_tracer.wgsl"
//
// Invocation (i, j) renders pixel (i, j) * stride + offset of the full image, with that pixel's own
// sampler sequence, accumulation and G-buffer entry: over stride x stride frames of offsets that
// visit every pixel of a block (`subset_offset`), each pixel takes the samples a whole-image
// dispatch would have given it (TemporalUpsampling).

// pixel_subset: (stride, offset x, offset y, unused) (SUBSET_GROUP).
//! include "generated/bindings/subset.wgsl"

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main_subset(@builtin(global_invocation_id) id: vec3<u32>) {
    render_pixel(id.xy * pixel_subset.x + pixel_subset.yz, 1u);
}
