// LightSample: a light seen from a receiving point, as sample_light and every light kind return it.
//! include "generated/structs.wgsl"

struct LightSample {
    // the light point (lights at a finite distance)
    position: vec3<f32>,
    // unit normal of the light's surface there (triangles shine from both sides); lights without a
    // surface give the direction from the light towards the receiver, so that its cosine is 1
    normal: vec3<f32>,
    // the radiance arriving from it (delta lights: the irradiance at normal incidence)
    radiance: vec3<f32>,
    // the light table's word for a triangle (light_table); 0 for other lights
    triangle: u32,
    // density of the direction from the receiving point per steradian, its light's selection
    // probability included; for delta lights the selection probability alone
    pdf: f32,
    // distant lights: the unit direction towards the light, along which shadow rays run to infinity
    direction: vec3<f32>,
    distant: bool,
    // a point or a single direction: found by light sampling only (weight 1)
    delta: bool,
}

// A sample that contributes nothing (a zeroed record's kind): zero radiance, a density of 1.
fn no_light_sample() -> LightSample {
    return LightSample(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0u, 1.0, vec3<f32>(0.0), false, true);
}

// `sample` drawn after its light was chosen with `probability`.
fn with_probability(sample: LightSample, probability: f32) -> LightSample {
    var chosen = sample;
    chosen.pdf *= probability;
    return chosen;
}
