// A first vertex's reservoir shared with its neighbours' (vertex_reservoir), where the restir
// integrator is compiled with RESERVOIR_NEIGHBOURS > 0 and the whole image is traced. A pre-pass
// (candidates.wgsl) makes every pixel's reservoir for this sample first (restir_reservoirs,
// restir_receivers); the path then combines its own with RESERVOIR_NEIGHBOURS others drawn within
// RESERVOIR_RADIUS pixels, by the generalised balance heuristic (Lin et al. 2022's GRIS): a sample
// from any reservoir is weighed by each reservoir's confidence M times its own target at that
// reservoir's receiver, so the weights of every sample sum to one over the reservoirs that could
// have given it. The targets are the unshadowed contribution and the shadow ray runs at this point
// only: a neighbour's sample occluded here adds nothing, and no visibility is reused, so the
// estimate's expectation is the direct light exactly. Neighbours whose surface faces elsewhere or
// lies at another depth are left out (their samples would rarely suit this point); which ones
// depends on their geometry alone, not on their samples.
//! include "generated/bindings/pixels.wgsl"

// How far away (pixels) the RESERVOIR_NEIGHBOURS neighbours are drawn.
override RESERVOIR_RADIUS: f32 = 10.0;
// The largest neighbours' reservoirs a combination holds (RESERVOIR_NEIGHBOURS at most).
const RESERVOIR_NEIGHBOURS_MAX: u32 = 6u;
// A neighbour is left out where its shading normal turns from this point's by more than this
// cosine allows, or its point lies off this point's tangent plane by more than this fraction of
// the distance to the camera (Bitterli et al.'s 25 degrees and 10%).
const NEIGHBOUR_MIN_COSINE: f32 = 0.906;
const NEIGHBOUR_MAX_PLANE_DISTANCE: f32 = 0.1;

// What candidate_reservoir draws, drawn and left: the pre-pass drew them for this sample.
fn skip_candidate_draws() {
    for (var candidate = 0u; candidate < RESAMPLED_LIGHT_CANDIDATES; candidate++) {
        sample_2d();
        sample_2d();
        sample_1d();
    }
}

// The target at `receiver` of `kept`, resampled at another point.
fn target_at(receiver: ShadedPoint, kept: ResampledLight) -> f32 {
    return resampled_light(receiver, light_seen_from(kept, receiver.p), kept.index).target_value;
}

// A reservoir as the pre-pass keeps it for its pixel (ReservoirRecord), and back.
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

// The pre-pass's reservoir of `pixel`: its sample, W and receiver. Empty (M 0) where the pre-pass
// did not resample.
struct PixelReservoir {
    sample: ResampledLight,
    weight: f32,
    receiver: ReservoirReceiver,
}

fn pixel_reservoir(pixel: u32) -> PixelReservoir {
    let record = restir_reservoirs[pixel];
    return PixelReservoir(stored_light(record), record.weight, restir_receivers[pixel]);
}

fn is_receiver(receiver: ReservoirReceiver, point: ShadedPoint) -> bool {
    return receiver.count > 0.0 && receiver.triangle == point.triangle_index && all(receiver.point == point.p);
}

// Whether a neighbour's receiver is close enough in orientation and depth to `point` to share
// its light samples usefully.
fn suits(point: ShadedPoint, neighbour: ShadedPoint) -> bool {
    let depth = length(point.p - frame.camera_position);
    let off_plane = abs(dot(neighbour.p - point.p, point.local.normal));
    return dot(point.local.normal, neighbour.local.normal) >= NEIGHBOUR_MIN_COSINE && off_plane <= NEIGHBOUR_MAX_PLANE_DISTANCE * depth;
}

// `point`'s reservoir (`own`, W `own_weight`) combined with its suitable neighbours' from the pre-pass.
// A combination of reservoirs: the survivor's reservoir and how many reservoirs took part.
struct CombinedReservoir {
    reservoir: LightReservoir,
    reservoirs: u32,
}

fn spatial_reservoir(point: ShadedPoint, xy: vec2<u32>, own: ResampledLight, own_weight: f32) -> CombinedReservoir {
    var receivers: array<ShadedPoint, RESERVOIR_NEIGHBOURS_MAX>;
    var samples: array<ResampledLight, RESERVOIR_NEIGHBOURS_MAX>;
    var weights: array<f32, RESERVOIR_NEIGHBOURS_MAX>;
    var found = 0u;
    for (var draw = 0u; draw < min(RESERVOIR_NEIGHBOURS, RESERVOIR_NEIGHBOURS_MAX); draw++) {
        let u = sample_2d();
        // uniform in the disc of RESERVOIR_RADIUS pixels, this pixel left out
        let offset = RESERVOIR_RADIUS * sqrt(u.x) * vec2<f32>(cos(TWO_PI * u.y), sin(TWO_PI * u.y));
        let at = vec2<i32>(round(vec2<f32>(xy) + offset));
        if any(at < vec2<i32>(0)) || at.x >= i32(frame.width) || at.y >= i32(frame.height) || all(vec2<u32>(at) == xy) {
            continue;
        }
        let neighbour = pixel_reservoir(u32(at.y) * frame.width + u32(at.x));
        if neighbour.receiver.count <= 0.0 {
            continue;
        }
        let receiver = shaded_point(neighbour.receiver.triangle, neighbour.receiver.point, neighbour.receiver.towards_viewer);
        if !suits(point, receiver) {
            continue;
        }
        receivers[found] = receiver;
        samples[found] = neighbour.sample;
        weights[found] = neighbour.weight;
        found++;
    }
    var combined = empty_light_reservoir();
    // this point's own sample: its weight against the neighbours' targets for it
    var others = 0.0;
    for (var j = 0u; j < found; j++) {
        others += target_at(receivers[j], own);
    }
    let own_share = select(0.0, own.target_value / (own.target_value + others), own.target_value > 0.0);
    reservoir_update(&combined, own, own_share * own.target_value * own_weight, sample_1d());
    for (var i = 0u; i < found; i++) {
        let u_keep = sample_1d();
        let moved = resampled_light(point, light_seen_from(samples[i], point.p), samples[i].index);
        var total = moved.target_value;
        var mine = 0.0;
        for (var j = 0u; j < found; j++) {
            let value = target_at(receivers[j], samples[i]);
            total += value;
            if j == i {
                mine = value;
            }
        }
        // every reservoir has the same confidence (RESAMPLED_LIGHT_CANDIDATES), which cancels
        let share = select(0.0, mine / total, total > 0.0);
        let weight = share * moved.target_value * weights[i];
        if weight > 0.0 && weight <= FLOAT_MAX {
            reservoir_update(&combined, moved, weight, u_keep);
        }
    }
    return CombinedReservoir(combined, found + 1u);
}

fn vertex_reservoir(point: ShadedPoint, pixel: u32) -> VertexReservoir {
    // this pixel's reservoir from the pre-pass, or made again where the pre-pass saw another point
    let count = f32(RESAMPLED_LIGHT_CANDIDATES);
    var own: ResampledLight;
    var own_weight: f32;
    let stored = pixel_reservoir(pixel);
    if is_receiver(stored.receiver, point) {
        skip_candidate_draws();
        own = resampled_light(point, light_seen_from(stored.sample, point.p), stored.sample.index);
        own_weight = stored.weight;
    } else {
        let fresh = candidate_reservoir(point);
        own = fresh.kept;
        own_weight = contribution_weight(fresh) / count;
    }
    let xy = vec2<u32>(pixel % frame.width, pixel / frame.width);
    let combined = spatial_reservoir(point, xy, own, own_weight);
    let reservoir = combined.reservoir;
    return VertexReservoir(reservoir.kept, contribution_weight(reservoir), count * f32(combined.reservoirs));
}
