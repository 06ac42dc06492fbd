// The direct light at a path's first vertex by ReSTIR (Bitterli et al. 2020): resampled importance
// sampling (RIS: Talbot et al. 2005) of light candidates at every pixel, then reuse of the
// reservoirs of neighbouring pixels. One shadow ray, for the survivor.
//
// RESAMPLED_LIGHT_CANDIDATES candidates come from the light sampler (every light kind, by power),
// each weighed by its target over its density (light_reservoir.wgsl). The vertex's reservoir is
// its own (own_reservoir.wgsl) or, where the integrator shares them (RESERVOIR_NEIGHBOURS), its
// own combined with its neighbours' (shared_reservoirs.wgsl): the generated first_vertex_light
// file includes one of the two, which defines vertex_reservoir.
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

const RESAMPLES_FIRST_VERTEX: bool = true;

// Candidates per first vertex, measured by `python -m bench.restir` (bench/README.md). Overrides,
// as the next ones, so that the benchmark can measure others.
override RESAMPLED_LIGHT_CANDIDATES: u32 = 16u;
// Lobes whose density towards the mirror direction is above this (per steradian; a GGX lobe's is
// about 1 / (4 pi alpha^2)) take their light by MIS.
override RESAMPLING_MAX_LOBE_DENSITY: f32 = 10.0;
// Neighbours' reservoirs combined with a pixel's own (shared_reservoirs.wgsl; 0: its own alone):
// the integrator's constant (wgputrace.integrators.restir), which the Renderer's shader overrides
// may change.
override RESERVOIR_NEIGHBOURS: u32;
// The most frames' candidates the previous frame's reservoir counts as where render_frame keeps
// them (temporal_reservoirs.wgsl): the integrator's constant too.
override RESERVOIR_HISTORY_CAP: f32;
// Debugging (test_restir_weights): where on, a first vertex whose reservoir is a combination gives
// in place of its light what checked_weight_sum found: (|sum - 1|, 1, -reservoirs combined), and
// counts as so many light samples that no light its BSDF sample finds adds anything.
override RESERVOIR_CHECK_WEIGHT_SUMS: bool = false;
var<private> weight_sum_check: vec3<f32>;

// What the weight sum check of a combination of `reservoirs` reservoirs found: the survivor's
// shares summing to `sum` (vertex_reservoir's files call it).
fn checked_weight_sum(sum: f32, reservoirs: u32) {
    weight_sum_check = vec3<f32>(abs(sum - 1.0), 1.0, -f32(reservoirs));
}

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

fn contribution_weight(reservoir: LightReservoir) -> f32 {
    let kept = reservoir.kept.target_value;
    return select(0.0, reservoir.weight_sum / kept, kept > 0.0);
}

// A first vertex's reservoir as it is shaded: the kept sample, its W, and how many light samples
// the candidates it stands for count as against the vertex's BSDF sample (vertex_reservoir: the
// vertex's own, or shared with its neighbours').
struct VertexReservoir {
    kept: ResampledLight,
    weight: f32,
    light_samples: f32,
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
    weight_sum_check = vec3<f32>(0.0);
    var light: VertexLight;
    if resamples_at(point) {
        let reservoir = vertex_reservoir(point, pixel);
        light = VertexLight(shade_reservoir(point, reservoir.kept, reservoir.weight, reservoir.light_samples), reservoir.light_samples);
    } else {
        light = VertexLight(direct_light(point), 1.0);
    }
    if RESERVOIR_CHECK_WEIGHT_SUMS {
        return VertexLight(weight_sum_check, FLOAT_MAX);
    }
    return light;
}
