// The direct light at a path's first vertex by ReSTIR (Bitterli et al. 2020): resampled importance
// sampling (RIS: Talbot et al. 2005) of light candidates at every pixel, then reuse of the
// reservoirs of neighbouring pixels. One shadow ray, for the survivor.
//
// RESAMPLED_LIGHT_CANDIDATES candidates come from the light sampler (every light kind, by power),
// each weighed by its target over its density (light_reservoir.wgsl). Where the whole image is
// traced (SPATIAL_REUSE, generated), a pre-pass (candidates.wgsl) makes every pixel's reservoir
// for this sample first; the path then combines its own with RESERVOIR_NEIGHBOURS others drawn
// within RESERVOIR_RADIUS pixels, by the generalised balance heuristic (Lin et al. 2022's GRIS): a
// sample from any reservoir is weighed by each reservoir's confidence M times its own target at
// that reservoir's receiver, so the weights of every sample sum to one over the reservoirs that
// could have given it. The targets are the unshadowed contribution and the shadow ray runs at this
// point only: a neighbour's sample occluded here adds nothing, and no visibility is reused, so the
// estimate's expectation is the direct light exactly. Neighbours whose surface faces elsewhere or
// lies at another depth are left out (their samples would rarely suit this point); which ones
// depends on their geometry alone, not on their samples. The viewer's bands and subsets trace a
// part of the image, with no pre-pass: there a vertex keeps its own candidates.
//
// Light that the first vertex's BSDF sample finds still counts, weighed against the reservoir's
// sample by MIS (power heuristic) as against light samples, as many as the candidates the
// reservoir drew from (its own and its neighbours'): the reservoir's density has no closed form,
// and that many light samples' stands in for it. For any sample the two weights sum to one, and
// the reservoir's W gives an unbiased estimate of any function within its target's support chosen
// before its candidates were drawn, so the sum is unbiased whatever stands in. Near a BSDF's peak
// the BSDF's samples take the light; where the lobe is narrow (resamples_at) light candidates
// drawn by power almost never land in it, and such a vertex takes its light as the mis
// integrator's do, from one light sample.
//! include "integrators/restir/light_reservoir.wgsl"

// Candidates per first vertex, measured by `python -m bench.restir` (bench/README.md). Overrides,
// as the next ones, so that the benchmark can measure others.
override RESAMPLED_LIGHT_CANDIDATES: u32 = 16u;
// Lobes whose density towards the mirror direction is above this (per steradian; a GGX lobe's is
// about 1 / (4 pi alpha^2)) take their light by MIS.
override RESAMPLING_MAX_LOBE_DENSITY: f32 = 10.0;
// Neighbours' reservoirs combined with a pixel's own (the integrator's constant: 0 by default,
// wgputrace.integrators.restir), and how far away (pixels) they are drawn.
override RESERVOIR_NEIGHBOURS: u32;
override RESERVOIR_RADIUS: f32 = 10.0;
// The largest neighbours' reservoirs a combination holds (RESERVOIR_NEIGHBOURS at most).
const RESERVOIR_NEIGHBOURS_MAX: u32 = 6u;
// A neighbour is left out where its shading normal turns from this point's by more than this
// cosine allows, or its point lies off this point's tangent plane by more than this fraction of
// the distance to the camera (Bitterli et al.'s 25 degrees and 10%).
const NEIGHBOUR_MIN_COSINE: f32 = 0.906;
const NEIGHBOUR_MAX_PLANE_DISTANCE: f32 = 0.1;

// Whether `point`'s lobe is wide enough for light candidates to land in it.
fn resamples_at(point: ShadedPoint) -> bool {
    let mirror = vec3<f32>(-point.wi.x, -point.wi.y, point.wi.z);
    return bsdf_pdf(point.material, point.wi, mirror) <= RESAMPLING_MAX_LOBE_DENSITY;
}

// RIS over RESAMPLED_LIGHT_CANDIDATES light samples at `point`: its kept sample and unbiased
// contribution weight W = weight sum / (candidates x target).
fn candidate_reservoir(point: ShadedPoint) -> LightReservoir {
    var reservoir = empty_light_reservoir();
    for (var candidate = 0u; candidate < RESAMPLED_LIGHT_CANDIDATES; candidate++) {
        // every candidate draws the same numbers, kept or not, so the sampler's dimensions stay in step
        let index = choose_light(sample_2d());
        let light = sample_chosen_light(index, point.p, sample_2d());
        let u_keep = sample_1d();
        if !(light.pdf > 0.0) {
            continue;
        }
        let sample = resampled_light(point, light, index);
        // the same ratio as target / density in the target's measure
        let weight = sample.target_value / (light.pdf * reservoir_measure(light, point.p));
        if weight > 0.0 && weight <= FLOAT_MAX {
            reservoir_update(&reservoir, sample, weight, u_keep);
        }
    }
    return reservoir;
}

// What candidate_reservoir draws, drawn and left: the pre-pass drew them for this sample.
fn skip_candidate_draws() {
    for (var candidate = 0u; candidate < RESAMPLED_LIGHT_CANDIDATES; candidate++) {
        sample_2d();
        sample_2d();
        sample_1d();
    }
}

fn contribution_weight(reservoir: LightReservoir) -> f32 {
    let kept = reservoir.kept.target_value;
    return select(0.0, reservoir.weight_sum / kept, kept > 0.0);
}

// The target at `receiver` of `kept`, resampled at another point.
fn target_at(receiver: ShadedPoint, kept: ResampledLight) -> f32 {
    return resampled_light(receiver, light_seen_from(kept, receiver.p), kept.index).target_value;
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

// The light of the reservoir's kept sample at `point`, through its one shadow ray, times W and its
// MIS weight against BSDF sampling as `light_samples` light samples (delta lights: 1).
fn shade_reservoir(point: ShadedPoint, kept: ResampledLight, weight: f32, light_samples: f32) -> vec3<f32> {
    if !(weight > 0.0) || !light_reaches(point, kept.light, kept.unshadowed.direction) {
        return vec3<f32>(0.0);
    }
    var mis = 1.0;
    if !kept.light.delta {
        let bsdf_density = bsdf_pdf(point.material, point.wi, to_local(point.local, kept.unshadowed.direction));
        mis = power_heuristic(light_sampling_density(kept.light, kept.index, point.p), bsdf_density / light_samples);
    }
    return kept.unshadowed.value * (reservoir_measure(kept.light, point.p) * weight * mis);
}

fn first_vertex_light(point: ShadedPoint, pixel: u32) -> VertexLight {
    if !resamples_at(point) {
        return VertexLight(direct_light(point), 1.0);
    }
    let count = f32(RESAMPLED_LIGHT_CANDIDATES);
    if !SPATIAL_REUSE {
        let fresh = candidate_reservoir(point);
        return VertexLight(shade_reservoir(point, fresh.kept, contribution_weight(fresh) / count, count), count);
    }
    // this pixel's reservoir from the pre-pass, or made again where the pre-pass saw another point
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
        own_weight = contribution_weight(fresh) / f32(RESAMPLED_LIGHT_CANDIDATES);
    }
    let xy = vec2<u32>(pixel % frame.width, pixel / frame.width);
    let combined = spatial_reservoir(point, xy, own, own_weight);
    let light_samples = count * f32(combined.reservoirs);
    let reservoir = combined.reservoir;
    return VertexLight(shade_reservoir(point, reservoir.kept, contribution_weight(reservoir), light_samples), light_samples);
}
