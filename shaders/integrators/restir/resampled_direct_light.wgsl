// The direct light at a path's first vertex by ReSTIR (Bitterli et al. 2020): resampled importance
// sampling (RIS: Talbot et al. 2005) of light candidates, then reuse of the pixel's reservoir from
// its previous sample. One shadow ray, for the survivor.
//
// RESAMPLED_LIGHT_CANDIDATES candidates come from the light sampler (every light kind, by power),
// each weighed by its target over its density (light_reservoir.wgsl). The pixel's reservoir from
// its previous sample, resampled at another point of the pixel (another jitter, another frame's
// camera), is combined with this one by the generalised balance heuristic (Lin et al. 2022's
// GRIS): a sample from either reservoir is weighed by each reservoir's confidence M times its own
// target at that reservoir's receiver. Both targets are the unshadowed contribution, and the
// shadow ray runs at this point only, so a sample that another receiver saw but that is occluded
// here simply adds nothing: the estimate's expectation is the direct light exactly, with no
// visibility to reuse and no bias from it. The kept reservoir's confidence is capped at
// RESERVOIR_HISTORY_CAP samples' worth, so that it keeps taking in new candidates.
//
// Light that the first vertex's BSDF sample finds counts nothing (follows_resampled_vertex), as
// under light sampling alone: the resampled sample's density has no closed form to weigh it
// against the BSDF's. Where the BSDF's lobe is narrow (resamples_at), light candidates drawn by
// power almost never land in it while BSDF sampling does: such a vertex takes its light by MIS, as
// the mis integrator's do, and leaves the pixel's reservoir as it was. Which rule applies is a
// function of the vertex alone, so each is unbiased where it applies.
//! include "integrators/restir/light_reservoir.wgsl"

// Candidates per first vertex, measured by `python -m bench.restir` (bench/README.md). Overrides,
// as the next two, so that the benchmark can measure others.
override RESAMPLED_LIGHT_CANDIDATES: u32 = 16u;
// The most samples' candidates a pixel's kept reservoir stands for (its confidence M, in units of
// RESAMPLED_LIGHT_CANDIDATES): Bitterli et al. cap it at 20. 0: no reuse, candidates alone.
override RESERVOIR_HISTORY_CAP: f32 = 20.0;

// Lobes whose density towards the mirror direction is above this (per steradian; a GGX lobe's is
// about 1 / (4 pi alpha^2)) take their light by MIS: measured by `python -m bench.restir`.
override RESAMPLING_MAX_LOBE_DENSITY: f32 = 10.0;

// Whether `point`'s lobe is wide enough for light candidates to land in it.
fn resamples_at(point: ShadedPoint) -> bool {
    let mirror = vec3<f32>(-point.wi.x, -point.wi.y, point.wi.z);
    return bsdf_pdf(point.material, point.wi, mirror) <= RESAMPLING_MAX_LOBE_DENSITY;
}

// RIS over RESAMPLED_LIGHT_CANDIDATES light samples at `point`.
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

// The target at `receiver` of `kept`, resampled at another point.
fn target_at(receiver: ShadedPoint, kept: ResampledLight) -> f32 {
    return resampled_light(receiver, light_seen_from(kept, receiver.p), kept.index).target_value;
}

// Confidence-weighted balance heuristic: the share of a sample whose targets are `own` at the
// receiver of the reservoir it came from (confidence `own_count`) and `other` at the other's.
fn balance_weight(own: f32, own_count: f32, other: f32, other_count: f32) -> f32 {
    let mine = own * own_count;
    let total = mine + other * other_count;
    return select(0.0, mine / total, total > 0.0);
}

fn first_vertex_light(point: ShadedPoint, pixel: u32) -> VertexLight {
    if !resamples_at(point) {
        return VertexLight(direct_light(point), false);
    }
    return VertexLight(resampled_direct_light(point, pixel), true);
}

fn resampled_direct_light(point: ShadedPoint, pixel: u32) -> vec3<f32> {
    let fresh = candidate_reservoir(point);
    let fresh_count = f32(RESAMPLED_LIGHT_CANDIDATES);
    let u_keep = sample_1d();
    let fresh_sample = fresh.kept;
    // this point's unbiased contribution weight of the fresh sample is weight sum / (M x target)
    var fresh_weight = 0.0;
    if fresh_sample.target_value > 0.0 {
        fresh_weight = fresh.weight_sum / (fresh_count * fresh_sample.target_value);
    }
    var combined = LightReservoir(fresh_sample, 0.0);
    var count = fresh_count;
    let receiver = restir_receivers[pixel];
    let record = restir_reservoirs[pixel];
    if RESERVOIR_HISTORY_CAP > 0.0 && receiver.triangle != NO_TRIANGLE && receiver.count > 0.0 && record.weight > 0.0 {
        let previous = shaded_point(receiver.triangle, receiver.point, receiver.towards_viewer);
        let previous_count = min(receiver.count, RESERVOIR_HISTORY_CAP * fresh_count);
        // the fresh sample, weighed against the previous receiver's target for it
        let fresh_share = balance_weight(fresh_sample.target_value, fresh_count, target_at(previous, fresh_sample), previous_count);
        combined.weight_sum = fresh_share * fresh_sample.target_value * fresh_weight;
        // the previous sample, moved to this point: its light seen from here
        let stored = stored_light(record);
        let moved = resampled_light(point, light_seen_from(stored, point.p), stored.index);
        let previous_share = balance_weight(target_at(previous, stored), previous_count, moved.target_value, fresh_count);
        let weight = previous_share * moved.target_value * record.weight;
        if weight > 0.0 && weight <= FLOAT_MAX {
            reservoir_update(&combined, moved, weight, u_keep);
        }
        count += previous_count;
    } else {
        combined.weight_sum = fresh_sample.target_value * fresh_weight;
    }
    let kept = combined.kept;
    var contribution_weight = 0.0;
    if kept.target_value > 0.0 {
        contribution_weight = combined.weight_sum / kept.target_value;
    }
    restir_reservoirs[pixel] = reservoir_record(kept, contribution_weight);
    restir_receivers[pixel] = ReservoirReceiver(point.p, point.triangle_index, point.towards_viewer, count);
    if !(contribution_weight > 0.0) || !light_reaches(point, kept.light, kept.unshadowed.direction) {
        return vec3<f32>(0.0);
    }
    return kept.unshadowed.value * (reservoir_measure(kept.light, point.p) * contribution_weight);
}
