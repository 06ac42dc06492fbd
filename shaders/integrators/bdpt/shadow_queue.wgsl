// The camera subpath's shadow-ray queue: contributions that count where their ray is unblocked.
// Traced together once the subpath ends or the next vertex's might not fit (trace_camera_subpath).
//! include "geometry/hit_queries.wgsl"
//
// Why queued: llvmpipe runs eight invocations in lockstep, and a loop runs while any of them still
// needs it. Traced where they arise, a lane whose camera subpath ended idles while the others
// trace theirs; queued, the k-th rays of all eight traverse together. On door_ajar this makes bdpt
// 1.09x as fast (bench/README.md's log). The queue holds a whole path's rays up to max_depth 10
// ((10 - 1) 10 / 2: the vertex at depth d joins next-event estimation's light and up to
// 9 - d light vertices); deeper paths empty it on the way. A queue for max_depth 16 (120 rays) is
// hardly faster and compiles 6.5 s longer per scene (llvmpipe's compile time grows with the
// length of private arrays indexed at run time).
const BDPT_SHADOW_RAYS: u32 = 45u;

// A segment to test: `ray` from the moved origin, blocked by anything but `skip_triangle` before
// `t_max`.
struct ShadowRay {
    ray: Ray,
    t_max: f32,
    skip_triangle: u32,
}

// What a strategy adds if its shadow ray is unblocked (`value` 0: nothing to test).
struct Shadowed {
    shadow: ShadowRay,
    value: vec3<f32>,
}

fn nothing_shadowed() -> Shadowed {
    return Shadowed(ShadowRay(Ray(vec3<f32>(0.0), vec3<f32>(0.0)), 0.0, NO_TRIANGLE), vec3<f32>(0.0));
}

// The queue, struct of arrays (compiles faster than an array of Shadowed): origin and t_max,
// direction and skipped triangle (its bits), value.
var<private> queued_origins: array<vec4<f32>, BDPT_SHADOW_RAYS>;
var<private> queued_directions: array<vec4<f32>, BDPT_SHADOW_RAYS>;
var<private> queued_values: array<vec3<f32>, BDPT_SHADOW_RAYS>;
var<private> queued_count: u32;

// Queues `contribution` scaled by `scale` (the camera subpath's throughput) unless it is 0; the
// caller made room (unblocked_sum_unless_room).
fn queue_shadowed(contribution: Shadowed, scale: vec3<f32>) {
    let value = contribution.value * scale;
    if any(value != vec3<f32>(0.0)) {
        let shadow = contribution.shadow;
        queued_origins[queued_count] = vec4<f32>(shadow.ray.origin, shadow.t_max);
        queued_directions[queued_count] = vec4<f32>(shadow.ray.direction, bitcast<f32>(shadow.skip_triangle));
        queued_values[queued_count] = value;
        queued_count++;
    }
}

// The sum of the queued contributions whose shadow rays are unblocked; empties the queue.
fn unblocked_sum() -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < queued_count; k++) {
        let origin = queued_origins[k];
        let direction = queued_directions[k];
        if !occluded(Ray(origin.xyz, direction.xyz), origin.w, bitcast<u32>(direction.w)) {
            sum += queued_values[k];
        }
    }
    queued_count = 0u;
    return sum;
}

// unblocked_sum() where fewer than `rays` more would fit, else 0 (the queue kept).
fn unblocked_sum_unless_room(rays: u32) -> vec3<f32> {
    if queued_count + rays <= BDPT_SHADOW_RAYS {
        return vec3<f32>(0.0);
    }
    return unblocked_sum();
}
