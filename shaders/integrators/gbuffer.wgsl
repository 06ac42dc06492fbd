// The G-buffer: what the ray through each pixel's centre first hits, and where the previous frame's camera saw it.
//! include "shading/first_hit.wgsl"
//! include "generated/camera.wgsl"
//! include "generated/bindings/pixels.wgsl"
//
// The centre ray, not a sample's jittered one: a resting camera's G-buffer is the same frame
// after frame, so temporal accumulation's reprojection is then the identity, exactly.

// A ray that leaves the scene stands for the point this far along it: its motion is the camera's
// turn, its translation vanishing next to the distance.
const GBUFFER_SKY_DISTANCE: f32 = 1e5;

fn write_gbuffer(xy: vec2<u32>, pixel: u32) {
    let ray = camera_ray(xy, PIXEL_CENTRE, LENS_CENTRE);
    let hit = first_hit(ray);
    let p = select(ray.origin + GBUFFER_SKY_DISTANCE * ray.direction, hit.position, hit.found);
    // both through camera_raster, so a camera that did not move gives motion 0 exactly
    let now = camera_raster(frame, p);
    let before = camera_raster(previous_frame, p);
    let surface = select(0u, hit.material + 1u, hit.found);
    // clamped to [0, 1] as the guides are: an emitter's colour is its radiance
    let albedo = clamp(hit.albedo, vec3<f32>(0.0), vec3<f32>(1.0));
    gbuffer[pixel] = GBufferPixel(hit.normal, select(0.0, now.distance, hit.found), albedo, surface, before.position - now.position, before.distance, u32(before.seen));
}
