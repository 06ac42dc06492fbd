// Reservoirs as one pass keeps them for another to read (ReservoirRecord, ReservoirReceiver), and
// what a kept sample is worth at another receiver: shared by the spatial reuse
// (shared_reservoirs.wgsl) and the temporal one (temporal_reservoirs.wgsl).

// A neighbour is left out where its shading normal turns from this point's by more than this
// cosine allows, or its point lies off this point's tangent plane by more than this fraction of
// the distance to the camera (Bitterli et al.'s 25 degrees and 10%).
const NEIGHBOUR_MIN_COSINE: f32 = 0.906;
const NEIGHBOUR_MAX_PLANE_DISTANCE: f32 = 0.1;

// The target at `receiver` of `kept`, resampled at another point.
fn target_at(receiver: ShadedPoint, kept: ResampledLight) -> f32 {
    return resampled_light(receiver, light_seen_from(kept, receiver.p), kept.index).target_value;
}

// A reservoir as a pass keeps it for its pixel (ReservoirRecord), and back.
fn stored_light(record: ReservoirRecord) -> ResampledLight {
    let distant = (record.kind & RESERVOIR_DISTANT) != 0u;
    let delta = (record.kind & RESERVOIR_DELTA) != 0u;
    let position = select(record.point, vec3<f32>(0.0), distant);
    let direction = select(vec3<f32>(0.0), record.point, distant);
    let triangle = select(0u, record.light, !distant && !delta);
    let light = LightSample(position, record.normal, record.radiance, triangle, record.density, direction, distant, delta);
    return ResampledLight(light, record.light, UnshadowedLight(vec3<f32>(0.0), vec3<f32>(0.0)), 0.0);
}

fn reservoir_record(kept: ResampledLight, weight: f32) -> ReservoirRecord {
    let light = kept.light;
    let kind = select(0u, RESERVOIR_DISTANT, light.distant) | select(0u, RESERVOIR_DELTA, light.delta);
    return ReservoirRecord(select(light.position, light.direction, light.distant), kept.index, light.normal, kind, light.radiance, weight, light.pdf);
}

// A stored reservoir: its sample, W and receiver. Empty (M 0) where nothing was resampled.
struct PixelReservoir {
    sample: ResampledLight,
    weight: f32,
    receiver: ReservoirReceiver,
}

fn pixel_reservoir(record: ReservoirRecord, receiver: ReservoirReceiver) -> PixelReservoir {
    return PixelReservoir(stored_light(record), record.weight, receiver);
}

// The surface point a stored reservoir was resampled for, shaded again.
fn receiver_point(receiver: ReservoirReceiver) -> ShadedPoint {
    return shaded_point(receiver.triangle, receiver.point, receiver.towards_viewer);
}

// Whether a neighbour's receiver is close enough in orientation and depth to `point` to share
// its light samples usefully.
fn suits(point: ShadedPoint, neighbour: ShadedPoint) -> bool {
    let depth = length(point.p - frame.camera_position);
    let off_plane = abs(dot(neighbour.p - point.p, point.local.normal));
    return dot(point.local.normal, neighbour.local.normal) >= NEIGHBOUR_MIN_COSINE && off_plane <= NEIGHBOUR_MAX_PLANE_DISTANCE * depth;
}
