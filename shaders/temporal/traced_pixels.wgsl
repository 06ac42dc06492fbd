// This frame's traced pixels in an upsampled frame: one per block, at the same place in each.
//! include "generated/upsampling.wgsl"
//
// The including kernel binds `params` (UpsamplingParameters) and includes the image's bounds
// (temporal/gbuffer_neighbours.wgsl).

// The side of a block.
fn stride() -> i32 {
    return i32(params.factor);
}

// The traced pixel's place in each block.
fn subset_offset() -> vec2<i32> {
    return vec2<i32>(i32(params.offset_x), i32(params.offset_y));
}

// The traced pixel of the block at `block` (in blocks); outside the image in some blocks of its
// last row or column.
fn traced_pixel(block: vec2<i32>) -> vec2<i32> {
    return block * stride() + subset_offset();
}

// The index of the block of a traced pixel `xy`: its record in `traced` (traced_neighbourhoods.wgsl).
fn traced_index(xy: vec2<i32>) -> u32 {
    let block = vec2<u32>((xy - subset_offset()) / stride());
    let across = (params.width + params.factor - 1u) / params.factor;
    return block.y * across + block.x;
}
