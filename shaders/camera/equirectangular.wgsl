// EquirectangularCamera: every direction from one point, theta from up down the rows, phi from forward across the columns.
//! include "camera/camera.wgsl"
//
// frame's camera_right, camera_up and camera_forward are the unit basis. The image point (u, v)
// in [0, 1]^2 sees theta = pi v, phi = 2 pi (u - 1/2) (EquirectangularCamera's docstring): a
// solid angle of 2 pi^2 sin(theta) per unit of image area, so a ray's density per steradian over
// the whole image is 1 / (2 pi^2 sin theta).

const CAMERA_LENS: bool = false;
const CAMERA_PARALLEL: bool = false;

// At the poles a ray's density is infinite: light tracing leaves directions whose sine of theta is
// below this to the camera's own rays.
const EQUIRECTANGULAR_SIN_MIN: f32 = 1e-6;

fn camera_ray(pixel: vec2<u32>, jitter: vec2<f32>, lens: vec2<f32>) -> Ray {
    let uv = (vec2<f32>(pixel) + jitter) / vec2<f32>(f32(frame.width), f32(frame.height));
    let theta = PI * uv.y;
    let phi = TWO_PI * (uv.x - 0.5);
    let sin_theta = sin(theta);
    let direction = sin_theta * sin(phi) * frame.camera_right + cos(theta) * frame.camera_up + sin_theta * cos(phi) * frame.camera_forward;
    return Ray(frame.camera_position, normalize(direction));
}

fn equirectangular_pdf(sin_theta: f32) -> f32 {
    return 1.0 / (2.0 * PI * PI * sin_theta);
}

fn camera_ray_density(ray: Ray) -> f32 {
    let cos_theta = dot(ray.direction, frame.camera_up);
    return equirectangular_pdf(sqrt(max(1.0 - cos_theta * cos_theta, 0.0)));
}

fn camera_connection(p: vec3<f32>, lens: vec2<f32>) -> CameraConnection {
    let to_point = p - frame.camera_position;
    let local = vec3<f32>(dot(to_point, frame.camera_right), dot(to_point, frame.camera_up), dot(to_point, frame.camera_forward));
    let distance = length(local);
    let sin_theta = length(local.xz) / distance;
    if !(sin_theta > EQUIRECTANGULAR_SIN_MIN) {
        return unseen();
    }
    let u = atan2(local.x, local.z) * (0.5 * INV_PI) + 0.5;
    let v = acos(clamp(local.y / distance, -1.0, 1.0)) * INV_PI;
    let column = min(u32(u * f32(frame.width)), frame.width - 1u);
    let row = min(u32(v * f32(frame.height)), frame.height - 1u);
    return CameraConnection(row * frame.width + column, equirectangular_pdf(sin_theta), frame.camera_position, true);
}

// camera_ray's angles of the direction to `p`; a point across the image's left and right edge
// lands a whole image width away from its neighbours.
fn camera_raster(view: Frame, p: vec3<f32>) -> CameraRaster {
    let to_point = p - view.camera_position;
    let local = vec3<f32>(dot(to_point, view.camera_right), dot(to_point, view.camera_up), dot(to_point, view.camera_forward));
    let distance = length(local);
    let uv = vec2<f32>(atan2(local.x, local.z) * (0.5 * INV_PI) + 0.5, acos(clamp(local.y / distance, -1.0, 1.0)) * INV_PI);
    return CameraRaster(uv * vec2<f32>(f32(view.width), f32(view.height)), distance, distance > 0.0);
}
