// A frame's pixels and their neighbours in the G-buffer, as the temporal passes read them: bounds, indices, demodulation, the depth's gradient.
//! include "generated/structs.wgsl"
//! include "generated/display_constants.wgsl"
//! include "common/constants.wgsl"
//
// The including kernel binds `params` (with the image's width and height) and `gbuffer`.

// GBufferPixel.surface where nothing was hit: the sky.
const SKY_SURFACE: u32 = 0u;

// Radiance over this is what the filters move about; albedo channels below FILTER_ALBEDO_MIN
// (black materials, nothing hit) divide by it instead of by ~0.
fn demodulation(albedo: vec3<f32>) -> vec3<f32> {
    return max(albedo, vec3<f32>(FILTER_ALBEDO_MIN));
}

fn inside(xy: vec2<i32>) -> bool {
    return all(xy >= vec2<i32>(0)) && xy.x < i32(params.width) && xy.y < i32(params.height);
}

fn pixel_index(xy: vec2<i32>) -> u32 {
    return u32(xy.y) * params.width + u32(xy.x);
}

// Whether two G-buffer pixels saw the same material of the same object (or both the sky).
fn same_surface(a: GBufferPixel, b: GBufferPixel) -> bool {
    return a.surface == b.surface && a.object == b.object;
}

// How much the depth changes per pixel along x and y on the surface the pixel at `xy` sees: per
// axis the smaller of the two one-sided differences to neighbours on the same surface, so a
// silhouette beside the pixel does not count as its surface's slope.
fn depth_gradient(xy: vec2<i32>, here: GBufferPixel) -> vec2<f32> {
    return depth_gradient_over(xy, here, 1);
}

// depth_gradient from the neighbours `spacing` pixels away (a sparse G-buffer's), per pixel.
fn depth_gradient_over(xy: vec2<i32>, here: GBufferPixel, spacing: i32) -> vec2<f32> {
    var gradient = vec2<f32>(0.0);
    for (var axis = 0; axis < 2; axis++) {
        var smallest = FLOAT_MAX;
        for (var side = -1; side <= 1; side += 2) {
            var step = vec2<i32>(0);
            step[axis] = side * spacing;
            let neighbour = xy + step;
            if inside(neighbour) {
                let there = gbuffer[pixel_index(neighbour)];
                if same_surface(there, here) {
                    smallest = min(smallest, abs(there.depth - here.depth));
                }
            }
        }
        gradient[axis] = select(0.0, smallest / f32(spacing), smallest < FLOAT_MAX);
    }
    return gradient;
}

// One of the four grid points around a position: its offset from the one below and left of the
// position (0 or 1 per axis) and its bilinear weight.
struct BilinearTap {
    offset: vec2<i32>,
    weight: f32,
}

// The `k`-th (0 to 3) of the four grid points around a position `fraction` ([0, 1) per axis) beyond
// the grid point below and left of it.
fn bilinear_tap(fraction: vec2<f32>, k: u32) -> BilinearTap {
    let offset = vec2<u32>(k & 1u, k >> 1u);
    let along = select(1.0 - fraction, fraction, offset == vec2<u32>(1u));
    return BilinearTap(vec2<i32>(offset), along.x * along.y);
}
