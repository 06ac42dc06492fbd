// The restir integrator's pre-pass: before each sample of the whole image, every pixel's reservoir
// of light candidates at the sample's first vertex (restir_reservoirs, restir_receivers), which the
// path tracer's pass then combines with its neighbours' (resampled_direct_light.wgsl). It draws the
// sample's camera ray and candidates as that pass will, and leaves the sampler where it found it, so
// that the pass traces the same first vertex; where that vertex takes no resampled light (a miss,
// an emitter, a narrow lobe, max_depth 1) the pixel's reservoir is empty (M 0).
//! include "integrators/path_tracer.wgsl"

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main_prepass(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let pixel = id.y * frame.width + id.x;
    sampler_begin(pixel);
    let ray = camera_path(id.xy).ray;
    var record = ReservoirRecord(vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0.0, 0.0);
    var receiver = ReservoirReceiver(vec3<f32>(0.0), NO_TRIANGLE, vec3<f32>(0.0), 0.0);
    let hit = closest_hit(ray, FLOAT_MAX, NO_TRIANGLE);
    if hit.triangle != NO_TRIANGLE && frame.max_depth > 1u {
        let point = shaded_point(hit.triangle, ray.origin + hit.t * ray.direction, -ray.direction);
        if material_reflects(point.material) && samples_lights(point.material) && resamples_at(point) {
            let reservoir = candidate_reservoir(point);
            let count = f32(RESAMPLED_LIGHT_CANDIDATES);
            record = reservoir_record(reservoir.kept, contribution_weight(reservoir) / count);
            receiver = ReservoirReceiver(point.p, point.triangle_index, point.towards_viewer, count);
        }
    }
    restir_reservoirs[pixel] = record;
    restir_receivers[pixel] = receiver;
    sampler_end_rewound(pixel);
}
