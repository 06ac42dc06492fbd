// Camera rays through a uniformly jittered point of a pixel (a box filter); row 0 is the top.
//! include "geometry/scene_bindings.wgsl"
//! include "geometry/ray.wgsl"

fn camera_ray(pixel: vec2<u32>, jitter: vec2<f32>) -> Ray {
    let ndc = (vec2<f32>(pixel) + jitter) / vec2<f32>(f32(frame.width), f32(frame.height)) * 2.0 - 1.0;
    let direction = frame.camera_forward + ndc.x * frame.camera_right - ndc.y * frame.camera_up;
    return Ray(frame.camera_position, normalize(direction));
}
