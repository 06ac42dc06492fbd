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

// The motion record of the object a hit word's triangle belongs to: a world triangle's shape
// (triangle_objects), or the instance of its slot (record slot - 1).
fn object_motion(word: u32) -> ObjectMotion {
    let slot = instance_slot(word);
    if slot == 0u {
        return object_motions[triangle_objects[mesh_triangle(word)]];
    }
    return object_motions[slot - 1u];
}

// Where the point `p` of an object that moved since the previous frame was then.
fn previous_position(motion: ObjectMotion, p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(motion.previous_from_current0.xyz, p) + motion.previous_from_current0.w,
        dot(motion.previous_from_current1.xyz, p) + motion.previous_from_current1.w,
        dot(motion.previous_from_current2.xyz, p) + motion.previous_from_current2.w,
    );
}

fn write_gbuffer(xy: vec2<u32>, pixel: u32) {
    let ray = camera_ray(xy, PIXEL_CENTRE, LENS_CENTRE);
    let hit = first_hit(ray);
    var p = ray.origin + GBUFFER_SKY_DISTANCE * ray.direction;
    var before_p = p;
    var object = 0u;
    if hit.found {
        let motion = object_motion(hit.word);
        p = hit.position;
        // an object at rest has the identity's rows, which give p back exactly
        before_p = previous_position(motion, p);
        object = motion.object;
    }
    // both through camera_raster, so a camera and an object that did not move give motion 0 exactly
    let now = camera_raster(frame, p);
    let before = camera_raster(previous_frame, before_p);
    let surface = select(0u, hit.material + 1u, hit.found);
    // clamped to [0, 1] as the guides are: an emitter's colour is its radiance
    let albedo = clamp(hit.albedo, vec3<f32>(0.0), vec3<f32>(1.0));
    let previous_depth = select(0.0, before.distance, before.seen);
    gbuffer[pixel] = GBufferPixel(hit.normal, select(0.0, now.distance, hit.found), albedo, surface, before.position - now.position, previous_depth, object);
}
