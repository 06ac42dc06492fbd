// The perspective kinds' image plane at distance 1: where a point seen from the lens's centre lands, and a ray's density.
//! include "camera/camera.wgsl"
//
// camera_ray aims at forward + x right - y up with x, y uniform in [-1, 1] per image: frame's
// right and up are the half extents of the image plane at distance 1 along the unit forward axis.
// A ray at angle theta to it has density 1 / (A cos^3 theta) per steradian over the whole plane of
// area A = image_plane_area(): the density that light tracing's splats divide by (We = that / cos
// theta, one light path per camera sample, as every pixel's camera ray has its own light path).
// A thin lens's rays from any one lens point have the same density (pbrt-v4's
// PerspectiveCamera::PDF_We): its plane in focus is the image plane scaled by focus_distance.

// The camera's density per steradian of a ray at `cos_theta` to its axis, over the whole image.
fn image_plane_pdf(cos_theta: f32) -> f32 {
    return 1.0 / (image_plane_area() * cos_theta * cos_theta * cos_theta);
}

// Where the ray from the lens's centre to the point at `to_point` from it crosses the image:
// `pixel` (row-major index) and the cosine to the axis; `seen` false behind the camera or outside
// the picture.
struct ImagePlaneProjection {
    pixel: u32,
    cos_theta: f32,
    seen: bool,
}

fn image_plane_projection(to_point: vec3<f32>) -> ImagePlaneProjection {
    let forward = dot(to_point, frame.camera_forward);
    if !(forward > 0.0) {
        return ImagePlaneProjection(0u, 0.0, false);
    }
    let ndc = vec2<f32>(
        dot(to_point, frame.camera_right) / (forward * dot(frame.camera_right, frame.camera_right)),
        -dot(to_point, frame.camera_up) / (forward * dot(frame.camera_up, frame.camera_up)),
    );
    let raster = ndc_pixel(ndc);
    return ImagePlaneProjection(raster.pixel, forward / length(to_point), raster.seen);
}

// The pinhole's ray direction through the image point `ndc` (pixel_ndc's), not normalised: its
// component along the axis is 1.
fn image_plane_direction(ndc: vec2<f32>) -> vec3<f32> {
    return frame.camera_forward + ndc.x * frame.camera_right - ndc.y * frame.camera_up;
}

// Where the point `p` lands in the image of the perspective camera `view`, seen from the lens's
// centre (view's camera_position): image_plane_projection for any Frame record, in raster units.
fn image_plane_raster(view: Frame, p: vec3<f32>) -> CameraRaster {
    let to_point = p - view.camera_position;
    let forward = dot(to_point, view.camera_forward);
    let ndc = vec2<f32>(
        dot(to_point, view.camera_right) / (forward * dot(view.camera_right, view.camera_right)),
        -dot(to_point, view.camera_up) / (forward * dot(view.camera_up, view.camera_up)),
    );
    return CameraRaster(ndc_raster(view, ndc), length(to_point), forward > 0.0);
}
