// ThinLensCamera: rays from a point of the lens disc through where the pinhole's ray meets the plane in focus.
//! include "camera/image_plane.wgsl"
//! include "sampling/warps.wgsl"

const CAMERA_LENS: bool = true;
const CAMERA_PARALLEL: bool = false;

// The lens point of lens sample `lens`: uniform on the disc of radius aperture_radius about the
// camera's position, in the image's right-up plane.
fn lens_point(lens: vec2<f32>) -> vec3<f32> {
    let disc = sample_concentric_disk(lens) * frame.aperture_radius;
    return frame.camera_position + disc.x * normalize(frame.camera_right) + disc.y * normalize(frame.camera_up);
}

fn camera_ray(pixel: vec2<u32>, jitter: vec2<f32>, lens: vec2<f32>) -> Ray {
    let in_focus = frame.camera_position + frame.focus_distance * image_plane_direction(pixel_ndc(pixel, jitter));
    let origin = lens_point(lens);
    return Ray(origin, normalize(in_focus - origin));
}

fn camera_ray_density(ray: Ray) -> f32 {
    return image_plane_pdf(dot(ray.direction, frame.camera_forward));
}

// The ray from the lens point through `p` meets the plane in focus where the pinhole's ray through
// the pixel it lands in does.
fn camera_connection(p: vec3<f32>, lens: vec2<f32>) -> CameraConnection {
    let origin = lens_point(lens);
    let to_point = p - origin;
    let along_axis = dot(to_point, frame.camera_forward);
    if !(along_axis > 0.0) {
        return unseen();
    }
    let in_focus = origin + to_point * (frame.focus_distance / along_axis);
    let projection = image_plane_projection(in_focus - frame.camera_position);
    return CameraConnection(projection.pixel, image_plane_pdf(along_axis / length(to_point)), origin, projection.seen);
}

fn camera_raster(view: Frame, p: vec3<f32>) -> CameraRaster {
    return image_plane_raster(view, p);
}
