// EmissionSample: a light path's first vertex, as sample_emission and every light kind return it.
//! include "generated/structs.wgsl"
//! include "sampling/warps.wgsl"

// A light path's start: a point on a light and a direction leaving it. Densities are per unit area
// (position) and per steradian (direction), so that radiance x cos / (pdf_position x pdf_direction)
// estimates the power the lights emit (cos = dot(normal, direction); 1 for lights without a
// surface). Distant lights start on a disc of the scene's bounding radius, perpendicular to
// `direction`, one radius behind the scene's centre, so that every ray from it crosses the scene.
struct EmissionSample {
    position: vec3<f32>,
    // the light's surface normal on the side `direction` leaves; lights without one: `direction`
    normal: vec3<f32>,
    // unit, leaving the light
    direction: vec3<f32>,
    // area lights: Le(position, direction); point and spot: the intensity I(direction); the
    // environment and the sun: the radiance arriving along -direction; directional: its irradiance
    radiance: vec3<f32>,
    // the light's selection probability x density per unit area (point, spot: the selection
    // probability alone; distant lights: over the disc, selection / (pi r^2))
    pdf_position: f32,
    // per steradian (directional: 1, a delta)
    pdf_direction: f32,
    // the light table's word (light_table): a triangle's index, LIGHT_SOURCE_FLAG | k or ENVIRONMENT_LIGHT
    triangle: u32,
    // point, spot
    delta_position: bool,
    // directional
    delta_direction: bool,
    // environment, sun, directional
    distant: bool,
}

// The densities sample_emission would have had for a given start, in EmissionSample's conventions.
struct EmissionPdf {
    position: f32,
    direction: f32,
}

// The scene's bounding sphere (SceneMirror.scene_bounding_sphere), where distant lights start.
struct SceneDisk {
    center: vec3<f32>,
    radius: f32,
}

// A sample that emits nothing (no light, a degenerate one): zero radiance, densities 1.
fn no_emission_sample() -> EmissionSample {
    let up = vec3<f32>(0.0, 0.0, 1.0);
    return EmissionSample(vec3<f32>(0.0), up, up, vec3<f32>(0.0), 1.0, 1.0, 0u, false, false, false);
}

// `sample` drawn after its light was chosen with `probability` (the light table's word `word`).
fn with_emission_probability(sample: EmissionSample, probability: f32, word: u32) -> EmissionSample {
    var chosen = sample;
    chosen.pdf_position *= probability;
    chosen.triangle = word;
    return chosen;
}

// Where a distant light's ray travelling along `direction` starts: uniform on the disc of `disk`'s
// radius perpendicular to it, one radius behind the centre.
fn distant_emission_origin(disk: SceneDisk, direction: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let frame = shading_frame(direction);
    return disk.center + disk.radius * to_world(frame, vec3<f32>(sample_uniform_disk(u), -1.0));
}

// The density per unit area of distant_emission_origin's points.
fn pdf_distant_emission_origin(disk: SceneDisk) -> f32 {
    return pdf_uniform_disk() / (disk.radius * disk.radius);
}

// A distant light's start: at the disc's point `u` for `direction`, its position density the disc's.
fn distant_emission_sample(disk: SceneDisk, u: vec2<f32>, direction: vec3<f32>, radiance: vec3<f32>, pdf_direction: f32, delta_direction: bool) -> EmissionSample {
    let position = distant_emission_origin(disk, direction, u);
    return EmissionSample(position, direction, direction, radiance, pdf_distant_emission_origin(disk), pdf_direction, 0u, false, delta_direction, true);
}

// What the distant lights that are not deltas (the environment, suns) send along one direction
// (the generated distant_emission): light paths from any of them count the radiance of all,
// with the density of their mixture, as a ray escaping the scene sees them all.
struct DistantEmission {
    radiance: vec3<f32>,
    // the sum of their selection probabilities
    selection: f32,
    // the sum over them of selection probability x density per steradian of the direction
    pdf: f32,
}

// The mixture's densities in EmissionSample's conventions: position, the disc's density times the
// summed selection probability; direction, the mixture's density given that one of them was chosen.
fn distant_emission_pdf(mixture: DistantEmission, disk: SceneDisk) -> EmissionPdf {
    if mixture.selection <= 0.0 {
        return EmissionPdf(0.0, 0.0);
    }
    return EmissionPdf(mixture.selection * pdf_distant_emission_origin(disk), mixture.pdf / mixture.selection);
}
