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
//! include "integrators/restir/reservoir_records.wgsl"

// How far away (pixels) the RESERVOIR_NEIGHBOURS neighbours are drawn.
override RESERVOIR_RADIUS: f32 = 10.0;
// The largest neighbours' reservoirs a combination holds (RESERVOIR_NEIGHBOURS at most).
const RESERVOIR_NEIGHBOURS_MAX: u32 = 6u;

// What candidate_reservoir draws, drawn and left: the pre-pass drew them for this sample.
fn skip_candidate_draws() {
    for (var candidate = 0u; candidate < RESAMPLED_LIGHT_CANDIDATES; candidate++) {
        sample_2d();
        sample_2d();
        sample_1d();
    }
}

// Whether `receiver` is the point `point` itself.
fn is_receiver(receiver: ReservoirReceiver, point: ShadedPoint) -> bool {
    return receiver.count > 0.0 && receiver.triangle == point.triangle_index && all(receiver.point == point.p);
}

// A combination of reservoirs: the survivor's reservoir and how many reservoirs took part.
struct CombinedReservoir {
    reservoir: LightReservoir,
    reservoirs: u32,
}

// The neighbours a combination found (spatial_reservoir): their receivers, samples and W.
var<private> neighbour_receivers: array<ShadedPoint, RESERVOIR_NEIGHBOURS_MAX>;
var<private> neighbour_samples: array<ResampledLight, RESERVOIR_NEIGHBOURS_MAX>;
var<private> neighbour_weights: array<f32, RESERVOIR_NEIGHBOURS_MAX>;
var<private> neighbours_found: u32;

// The share of `sample` (its target `here` at this point) that comes from reservoir `source` (0:
// this point's own, i + 1: the i-th neighbour's): its target at that reservoir's receiver over the
// sum of its targets at every receiver. Every reservoir has the same confidence
// (RESAMPLED_LIGHT_CANDIDATES), which cancels.
fn spatial_share(sample: ResampledLight, here: f32, source: u32) -> f32 {
    var total = here;
    var mine = select(0.0, here, source == 0u);
    for (var j = 0u; j < neighbours_found; j++) {
        let value = target_at(neighbour_receivers[j], sample);
        total += value;
        if j + 1u == source {
            mine = value;
        }
    }
    return select(0.0, mine / total, total > 0.0);
}

// The neighbours' reservoirs within RESERVOIR_RADIUS of `xy` whose receivers suit `point`.
fn find_neighbours(point: ShadedPoint, xy: vec2<u32>) {
    neighbours_found = 0u;
    for (var draw = 0u; draw < min(RESERVOIR_NEIGHBOURS, RESERVOIR_NEIGHBOURS_MAX); draw++) {
        let u = sample_2d();
        // uniform in the disc of RESERVOIR_RADIUS pixels, this pixel left out
        let offset = RESERVOIR_RADIUS * sqrt(u.x) * vec2<f32>(cos(TWO_PI * u.y), sin(TWO_PI * u.y));
        let at = vec2<i32>(round(vec2<f32>(xy) + offset));
        if any(at < vec2<i32>(0)) || at.x >= i32(frame.width) || at.y >= i32(frame.height) || all(vec2<u32>(at) == xy) {
            continue;
        }
        let index = u32(at.y) * frame.width + u32(at.x);
        let neighbour = pixel_reservoir(restir_reservoirs[index], restir_receivers[index]);
        if neighbour.receiver.count <= 0.0 {
            continue;
        }
        let receiver = receiver_point(neighbour.receiver);
        if !suits(point, receiver) {
            continue;
        }
        neighbour_receivers[neighbours_found] = receiver;
        neighbour_samples[neighbours_found] = neighbour.sample;
        neighbour_weights[neighbours_found] = neighbour.weight;
        neighbours_found++;
    }
}

// `point`'s reservoir (`own`, W `own_weight`) combined with its suitable neighbours' from the pre-pass.
fn spatial_reservoir(point: ShadedPoint, xy: vec2<u32>, own: ResampledLight, own_weight: f32) -> CombinedReservoir {
    find_neighbours(point, xy);
    var combined = empty_light_reservoir();
    reservoir_update(&combined, own, spatial_share(own, own.target_value, 0u) * own.target_value * own_weight, sample_1d());
    for (var i = 0u; i < neighbours_found; i++) {
        let u_keep = sample_1d();
        let sample = neighbour_samples[i];
        let moved = resampled_light(point, light_seen_from(sample, point.p), sample.index);
        let weight = spatial_share(sample, moved.target_value, i + 1u) * moved.target_value * neighbour_weights[i];
        if weight > 0.0 && weight <= FLOAT_MAX {
            reservoir_update(&combined, moved, weight, u_keep);
        }
    }
    if RESERVOIR_CHECK_WEIGHT_SUMS {
        check_spatial_shares(point, combined.kept);
    }
    return CombinedReservoir(combined, neighbours_found + 1u);
}

// The weight sum check (RESERVOIR_CHECK_WEIGHT_SUMS) of the combination's survivor `kept`: its
// shares as this point's own sample and as each neighbour would hold it (stored and seen again
// from here) sum to one.
fn check_spatial_shares(point: ShadedPoint, kept: ResampledLight) {
    if !(kept.target_value > 0.0) {
        return;
    }
    let held = stored_light(reservoir_record(kept, 0.0));
    let here = resampled_light(point, light_seen_from(held, point.p), held.index).target_value;
    var sum = spatial_share(kept, kept.target_value, 0u);
    for (var i = 0u; i < neighbours_found; i++) {
        sum += spatial_share(held, here, i + 1u);
    }
    checked_weight_sum(sum, neighbours_found + 1u);
}

fn vertex_reservoir(point: ShadedPoint, pixel: u32) -> VertexReservoir {
    // this pixel's reservoir from the pre-pass, or made again where the pre-pass saw another point
    let count = f32(RESAMPLED_LIGHT_CANDIDATES);
    var own: ResampledLight;
    var own_weight: f32;
    let stored = pixel_reservoir(restir_reservoirs[pixel], restir_receivers[pixel]);
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
