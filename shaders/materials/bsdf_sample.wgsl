// The result of sampling a BSDF, and the convention every material follows.
//
// Directions are in the local shading frame (normal = +z); wi points towards the viewer, wo
// towards the light. `<material>_eval` returns f(wi, wo) * |cos theta_o| (the cosine included),
// `<material>_pdf` the solid-angle density of `<material>_sample`, whose weight is eval / pdf.

struct BsdfSample {
    direction: vec3<f32>,
    weight: vec3<f32>,
    // solid-angle density; for a delta lobe, the discrete probability of choosing it
    pdf: f32,
    is_delta: bool,
    // eta_incident / eta_transmitted for a refraction (the factor whose square scales radiance),
    // 1 for reflections
    eta: f32,
}

fn no_bsdf_sample() -> BsdfSample {
    return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0, false, 1.0);
}
