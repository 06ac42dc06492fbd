// OrthographicCamera: parallel rays along forward from the points of a rectangle.
//! include "camera/camera.wgsl"
//
// frame's camera_right and camera_up are the rectangle's half extents in scene units, centred at
// camera_position; camera_forward is the rays' unit direction.

const CAMERA_LENS: bool = false;
const CAMERA_PARALLEL: bool = true;

fn camera_ray(pixel: vec2<u32>, jitter: vec2<f32>, lens: vec2<f32>) -> Ray {
    let ndc = pixel_ndc(pixel, jitter);
    return Ray(frame.camera_position + ndc.x * frame.camera_right - ndc.y * frame.camera_up, frame.camera_forward);
}

// Uniform over the rectangle: per unit area of the ray's origin.
fn camera_ray_density(ray: Ray) -> f32 {
    return 1.0 / image_plane_area();
}

// The point of the rectangle that `p` lies straight in front of.
fn camera_connection(p: vec3<f32>, lens: vec2<f32>) -> CameraConnection {
    let to_point = p - frame.camera_position;
    let along_axis = dot(to_point, frame.camera_forward);
    if !(along_axis > 0.0) {
        return unseen();
    }
    let ndc = vec2<f32>(
        dot(to_point, frame.camera_right) / dot(frame.camera_right, frame.camera_right),
        -dot(to_point, frame.camera_up) / dot(frame.camera_up, frame.camera_up),
    );
    let raster = ndc_pixel(ndc);
    return CameraConnection(raster.pixel, 1.0 / image_plane_area(), p - along_axis * frame.camera_forward, raster.seen);
}

// The rectangle's point straight behind `p`, and the distance along forward from it.
fn camera_raster(view: Frame, p: vec3<f32>) -> CameraRaster {
    let to_point = p - view.camera_position;
    let along_axis = dot(to_point, view.camera_forward);
    let ndc = vec2<f32>(
        dot(to_point, view.camera_right) / dot(view.camera_right, view.camera_right),
        -dot(to_point, view.camera_up) / dot(view.camera_up, view.camera_up),
    );
    return CameraRaster(ndc_raster(view, ndc), along_axis, along_axis > 0.0);
}
