// Camera, the pinhole: rays from one point through the image plane; light tracing joins a point to that point.
//! include "camera/image_plane.wgsl"

const CAMERA_LENS: bool = false;
const CAMERA_PARALLEL: bool = false;

fn camera_ray(pixel: vec2<u32>, jitter: vec2<f32>, lens: vec2<f32>) -> Ray {
    return Ray(frame.camera_position, normalize(image_plane_direction(pixel_ndc(pixel, jitter))));
}

fn camera_ray_density(ray: Ray) -> f32 {
    return image_plane_pdf(dot(ray.direction, frame.camera_forward));
}

fn camera_connection(p: vec3<f32>, lens: vec2<f32>) -> CameraConnection {
    let projection = image_plane_projection(p - frame.camera_position);
    return CameraConnection(projection.pixel, image_plane_pdf(projection.cos_theta), frame.camera_position, projection.seen);
}

fn camera_raster(view: Frame, p: vec3<f32>) -> CameraRaster {
    return image_plane_raster(view, p);
}
