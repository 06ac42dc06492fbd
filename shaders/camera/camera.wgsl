// What every camera kind's WGSL provides (its class's `shader`, included as generated/camera.wgsl), and what they share.
//! include "geometry/scene_bindings.wgsl"
//! include "geometry/ray.wgsl"
//
// A kind's file defines
// - CAMERA_LENS: whether camera_ray takes a lens sample; the integrators draw one (lens_sample)
//   only then, so the other kinds draw the sampler's dimensions they always did;
// - CAMERA_PARALLEL: whether its rays share one direction (their density is then per unit area
//   of their origins, not per steradian);
// - camera_ray(pixel, jitter, lens): the ray through point `jitter` of `pixel` (in [0, 1)^2: a
//   box filter), row 0 on top, from lens sample `lens` (LENS_CENTRE: the lens's centre);
// - camera_ray_density(ray): the density with which camera_ray, over the whole image, makes `ray`
//   (per steradian, or per unit area for a parallel camera; for a camera with a lens, given its
//   point on the lens);
// - camera_connection(p, lens): how light tracing joins point `p` to the camera at lens sample
//   `lens` (CameraConnection);
// - camera_raster(view, p): where point `p` lands in the image of the camera `view` (a Frame
//   record: this frame's, or the previous frame's for motion vectors), seen from the lens's
//   centre: the inverse of camera_ray at LENS_CENTRE (CameraRaster).

// The lens sample of a ray through the lens's centre (sample_concentric_disk's centre).
const LENS_CENTRE: vec2<f32> = vec2<f32>(0.5, 0.5);

// Light tracing's way from a point to the camera: the pixel it lands in, the camera's density of
// the ray from `position` (the camera's point it reaches: the pinhole, the lens point, a point of
// the orthographic rectangle) through it (as camera_ray_density), and whether the camera sees it.
struct CameraConnection {
    pixel: u32,
    pdf: f32,
    position: vec3<f32>,
    seen: bool,
}

fn unseen() -> CameraConnection {
    return CameraConnection(0u, 0.0, vec3<f32>(0.0), false);
}

// The point `jitter` of `pixel` in [-1, 1]^2 over the image (y down: row 0 on top).
fn pixel_ndc(pixel: vec2<u32>, jitter: vec2<f32>) -> vec2<f32> {
    return (vec2<f32>(pixel) + jitter) / vec2<f32>(f32(frame.width), f32(frame.height)) * 2.0 - 1.0;
}

// The row-major index of the pixel at `ndc` (pixel_ndc's coordinates); `seen` false outside the image.
struct ImagePixel {
    pixel: u32,
    seen: bool,
}

fn ndc_pixel(ndc: vec2<f32>) -> ImagePixel {
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let raster = (ndc * 0.5 + 0.5) * size;
    if !(all(raster >= vec2<f32>(0.0)) && all(raster < size)) {
        return ImagePixel(0u, false);
    }
    let column = min(u32(raster.x), frame.width - 1u);
    let row = min(u32(raster.y), frame.height - 1u);
    return ImagePixel(row * frame.width + column, true);
}

// A point in the image of a camera: its raster `position` in pixels (x right, y down, the centre of
// pixel (i, j) at (i + 0.5, j + 0.5), not limited to the image), the distance the camera's ray
// travels to it (the G-buffer's depth), and whether it lies in front of the camera.
struct CameraRaster {
    position: vec2<f32>,
    distance: f32,
    seen: bool,
}

// Raster position of the image point `ndc` (pixel_ndc's coordinates) in the image of `view`.
fn ndc_raster(view: Frame, ndc: vec2<f32>) -> vec2<f32> {
    return (ndc * 0.5 + 0.5) * vec2<f32>(f32(view.width), f32(view.height));
}

// The area of the image's rectangle spanned by frame's camera_right and camera_up (its half
// extents): at distance 1 for the perspective kinds, in scene units for the orthographic one.
fn image_plane_area() -> f32 {
    return 4.0 * length(frame.camera_right) * length(frame.camera_up);
}
