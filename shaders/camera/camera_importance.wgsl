// The pinhole camera seen from the scene: where a point lands on the image, and its ray's density.
// That density is the importance We of camera_ray's jittered box filter, which light tracing needs.
//! include "geometry/scene_bindings.wgsl"
//! include "common/constants.wgsl"
//
// camera_ray aims at forward + x right - y up with x, y uniform in [-1, 1] per image: frame's
// right and up are the half extents of the image plane at distance 1 along the unit forward axis.
// A ray at angle theta to it has density 1 / (A cos^3 theta) per steradian over the whole plane of
// area A = 4 |right| |up|: the density that light tracing's splats divide by (We = that / cos theta,
// one light path per camera sample, as every pixel's camera ray has its own light path).

fn image_plane_area() -> f32 {
    return 4.0 * length(frame.camera_right) * length(frame.camera_up);
}

// The camera's density per steradian of a ray at `cos_theta` to its axis, over the whole image.
fn camera_ray_pdf(cos_theta: f32) -> f32 {
    return 1.0 / (image_plane_area() * cos_theta * cos_theta * cos_theta);
}

// Where the ray from the camera through `p` crosses the image: `pixel` (row-major index) and the
// cosine to the axis; `seen` false behind the camera or outside the picture.
struct CameraProjection {
    pixel: u32,
    cos_theta: f32,
    seen: bool,
}

fn camera_projection(p: vec3<f32>) -> CameraProjection {
    let to_point = p - frame.camera_position;
    let forward = dot(to_point, frame.camera_forward);
    if !(forward > 0.0) {
        return CameraProjection(0u, 0.0, false);
    }
    let ndc = vec2<f32>(
        dot(to_point, frame.camera_right) / (forward * dot(frame.camera_right, frame.camera_right)),
        -dot(to_point, frame.camera_up) / (forward * dot(frame.camera_up, frame.camera_up)),
    );
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let raster = (ndc * 0.5 + 0.5) * size;
    if !(all(raster >= vec2<f32>(0.0)) && all(raster < size)) {
        return CameraProjection(0u, 0.0, false);
    }
    let column = min(u32(raster.x), frame.width - 1u);
    let row = min(u32(raster.y), frame.height - 1u);
    return CameraProjection(row * frame.width + column, forward / length(to_point), true);
}
