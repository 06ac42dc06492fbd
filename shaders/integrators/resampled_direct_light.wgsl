// The direct light at a path's first vertex by resampled importance sampling (RIS: Talbot et al.
// 2005), ReSTIR's first step (Bitterli et al. 2020). RESAMPLED_LIGHT_CANDIDATES candidates come
// from the light sampler (every light kind, by power); each is weighed by its target, the
// luminance of its unshadowed contribution, over its density; one survivor, kept by weighted
// reservoir sampling, gets the only shadow ray. Its contribution times its unbiased contribution
// weight W = weight sum / (candidates x target) has the direct light as its expectation: the target
// is positive wherever the contribution is, and the light sampler reaches every light. Where light
// is many and small, the candidates' targets find the few that matter to this point (near it,
// facing it, in the BSDF's lobe) among the many the power table draws alike.
//
// Light that the first vertex's BSDF sample finds counts nothing (follows_resampled_vertex), as
// under light sampling alone: RIS's density has no closed form to weigh it against the BSDF's.

const RESAMPLES_FIRST_VERTEX: bool = true;
// Candidates per first vertex: measured by `python -m bench.restir` (bench/README.md).
const RESAMPLED_LIGHT_CANDIDATES: u32 = 16u;

// The reservoir of one light sample: the candidate kept with its unshadowed contribution and
// target, and the sum of every candidate's resampling weight.
struct LightReservoir {
    light: LightSample,
    unshadowed: UnshadowedLight,
    target_value: f32,
    weight_sum: f32,
}

fn empty_light_reservoir() -> LightReservoir {
    return LightReservoir(no_light_sample(), UnshadowedLight(vec3<f32>(0.0), vec3<f32>(0.0)), 0.0, 0.0);
}

// `reservoir` having seen one more candidate of resampling weight `weight`, kept with probability
// weight / weight sum by the uniform draw `u_keep` (Chao's streaming selection).
fn reservoir_update(reservoir: ptr<function, LightReservoir>, light: LightSample, unshadowed: UnshadowedLight, target_value: f32, weight: f32, u_keep: f32) {
    (*reservoir).weight_sum += weight;
    if u_keep * (*reservoir).weight_sum < weight {
        (*reservoir).light = light;
        (*reservoir).unshadowed = unshadowed;
        (*reservoir).target_value = target_value;
    }
}

fn first_vertex_light(p: vec3<f32>, triangle: Triangle, triangle_index: u32, local: ShadingFrame, geometric: vec3<f32>, towards_viewer: vec3<f32>, material: Material, wi: vec3<f32>) -> vec3<f32> {
    var reservoir = empty_light_reservoir();
    for (var candidate = 0u; candidate < RESAMPLED_LIGHT_CANDIDATES; candidate++) {
        // every candidate draws the same numbers, kept or not, so the sampler's dimensions stay in step
        let light = sample_light(p, sample_2d(), sample_2d());
        let u_keep = sample_1d();
        if !(light.pdf > 0.0) {
            continue;
        }
        let unshadowed = unshadowed_light(p, local, geometric, towards_viewer, material, wi, light);
        let target_value = luminance(unshadowed.value);
        let weight = target_value / light.pdf;
        // zero (behind the surface, outside the lobe) adds nothing; an overflow would make the sum infinite
        if weight > 0.0 && weight <= FLOAT_MAX {
            reservoir_update(&reservoir, light, unshadowed, target_value, weight, u_keep);
        }
    }
    if !(reservoir.target_value > 0.0) || !light_reaches(p, triangle, triangle_index, geometric, reservoir.light, reservoir.unshadowed.direction) {
        return vec3<f32>(0.0);
    }
    let contribution_weight = reservoir.weight_sum / (f32(RESAMPLED_LIGHT_CANDIDATES) * reservoir.target_value);
    return reservoir.unshadowed.value * contribution_weight;
}
