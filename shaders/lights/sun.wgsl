// The sun: a distant disc of uniform radiance, sampled uniformly in its cone; sample beside pdf.
//! include "lights/direct_light_sample.wgsl"
//! include "sampling/warps.wgsl"
//! include "lights/light_path_sample.wgsl"

// Whether `direction` (towards the sky) lies in the sun's disc. Compared through the squared sine
// of its angle to the axis, which f32 keeps to 7 digits where the cosine of a 0.27 degree angle
// keeps 3 (light.cone = 1 - cos of the disc's angular radius, from float64 on the host).
fn sun_contains(light: LightSource, direction: vec3<f32>) -> bool {
    let off_axis = cross(direction, light.direction);
    return dot(direction, light.direction) < 0.0 && dot(off_axis, off_axis) <= light.cone * (2.0 - light.cone);
}

fn sun_pdf(light: LightSource, direction: vec3<f32>) -> f32 {
    return select(0.0, pdf_uniform_cone(light.cone), sun_contains(light, direction));
}

fn sun_escaped_radiance(light: LightSource, direction: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), light.emission, sun_contains(light, direction));
}

// Uniform in the cone around -light.direction.
fn sun_sample(light: LightSource, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let direction = to_world(shading_frame(-light.direction), sample_uniform_cone(u, light.cone));
    return LightSample(p, -direction, light.emission, 0u, pdf_uniform_cone(light.cone), direction, true, false);
}

// Light paths from the sun: a direction of its cone as sun_sample draws it, from the scene's disc.
fn sun_emission_sample(light: LightSource, disk: SceneDisk, u_position: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    let towards = sun_sample(light, disk.center, u_direction);
    return distant_emission_sample(disk, u_position, -towards.direction, light.emission, towards.pdf, false);
}
