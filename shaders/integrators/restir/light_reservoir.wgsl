// The restir integrator's reservoirs: a light sample chosen in proportion to a target among
// candidates, with the sum of their resampling weights.
//
// Samples are compared across surface points in one measure: per unit area of light for lights at
// a finite distance (triangles, whose points every receiver shares), per steradian for distant
// lights and per light for delta ones (whose directions or selves it shares). The target at a
// receiver is the luminance of the sample's unshadowed contribution there in that measure
// (target_value): 0 behind the surface or outside the BSDF's lobe, so a reservoir's sample can be
// reused wherever the target is positive.

const RESERVOIR_DISTANT: u32 = 1u;
const RESERVOIR_DELTA: u32 = 2u;

// A light sample as resampling handles it: the light as seen from the receiver, the light table's
// word it came from, its unshadowed contribution and target there.
struct ResampledLight {
    light: LightSample,
    index: u32,
    unshadowed: UnshadowedLight,
    target_value: f32,
}

// The reservoir of one light sample: the candidate kept and the sum of every candidate's
// resampling weight.
struct LightReservoir {
    kept: ResampledLight,
    weight_sum: f32,
}

fn no_resampled_light() -> ResampledLight {
    return ResampledLight(no_light_sample(), 0u, UnshadowedLight(vec3<f32>(0.0), vec3<f32>(0.0)), 0.0);
}

fn empty_light_reservoir() -> LightReservoir {
    return LightReservoir(no_resampled_light(), 0.0);
}

// `reservoir` having seen one more candidate of resampling weight `weight`, kept with probability
// weight / weight sum by the uniform draw `u_keep` (Chao's streaming selection).
fn reservoir_update(reservoir: ptr<function, LightReservoir>, candidate: ResampledLight, weight: f32, u_keep: f32) {
    (*reservoir).weight_sum += weight;
    if u_keep * (*reservoir).weight_sum < weight {
        (*reservoir).kept = candidate;
    }
}

// The factor from a light sample's density per steradian at `p` to its measure: cos / d^2 for a
// light at a finite distance with a surface; 1 for distant and delta lights.
fn reservoir_measure(light: LightSample, p: vec3<f32>) -> f32 {
    if light.distant || light.delta {
        return 1.0;
    }
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    return abs(dot(light.normal, to_light)) / (distance_squared * sqrt(distance_squared));
}

// `light` (from the light table's word `index`) resampled at `point`.
fn resampled_light(point: ShadedPoint, light: LightSample, index: u32) -> ResampledLight {
    let unshadowed = unshadowed_light(point, light);
    let target_value = luminance(unshadowed.value) * reservoir_measure(light, point.p);
    // NaN and infinity to 0: no sample's weight may poison a sum
    return ResampledLight(light, index, unshadowed, select(0.0, target_value, target_value >= 0.0 && target_value <= FLOAT_MAX));
}

// The kept sample's light seen from `p`: a triangle's point keeps its place and normal and shines
// towards `p` as its material and texture say; a point or spot light is sampled again from `p`
// (it has one point); a distant light keeps its direction and radiance.
fn light_seen_from(kept: ResampledLight, p: vec3<f32>) -> LightSample {
    if kept.light.delta && !kept.light.distant {
        return sample_chosen_light(kept.index, p, vec2<f32>(0.5));
    }
    if kept.light.distant {
        return kept.light;
    }
    let triangle = scene_triangle(kept.index);
    var light = kept.light;
    light.radiance = material_emitted(materials[triangle.material]) + surface_emission(triangle.material, kept.index, triangle, light.position, light.position - p);
    return light;
}

// The light sampler's density (per steradian, its choice included) of `light`'s direction from
// `p`: a triangle's from its place, a distant light's as it was sampled (the same from everywhere).
fn light_sampling_density(light: LightSample, index: u32, p: vec3<f32>) -> f32 {
    if light.distant || light.delta {
        return light.pdf;
    }
    let triangle = scene_triangle(index);
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    return pdf_light(p, index, triangle, distance_squared, abs(dot(light.normal, to_light)) / sqrt(distance_squared));
}
