// Spot lights: a point light whose intensity falls linearly in angle from its beam to its cutoff (Mitsuba's `spot`).
//! include "lights/direct_light_sample.wgsl"
//! include "lights/light_path_sample.wgsl"

// The fraction of the axis intensity sent at `cos_theta` from the axis: 1 within the beam width,
// 0 from the cutoff angle on, linear in the angle between (Mitsuba 3's falloff_curve). Clamped to
// 1 so that a beam as wide as its cutoff (inverse_transition huge) is a hard edge.
fn spot_falloff(light: LightSource, cos_theta: f32) -> f32 {
    if cos_theta <= light.cos_outer {
        return 0.0;
    }
    if cos_theta >= light.cos_inner {
        return 1.0;
    }
    return min((light.angle_outer - acos(cos_theta)) * light.inverse_transition, 1.0);
}

fn spot_light_sample(light: LightSource, p: vec3<f32>) -> LightSample {
    let to_light = light.position - p;
    let distance_squared = dot(to_light, to_light);
    let from_light = -to_light * inverseSqrt(distance_squared);
    let radiance = light.emission * (spot_falloff(light, dot(from_light, light.direction)) / distance_squared);
    return LightSample(light.position, from_light, radiance, 0u, 1.0, vec3<f32>(0.0), false, true);
}

// Light paths from a spot light: uniform in its cutoff cone (light.cone = 1 - cos_outer, from
// float64 on the host), each direction carrying its falloff.
fn spot_emission_sample(light: LightSource, u: vec2<f32>) -> EmissionSample {
    let direction = to_world(shading_frame(light.direction), sample_uniform_cone(u, light.cone));
    let radiance = light.emission * spot_falloff(light, dot(direction, light.direction));
    return EmissionSample(light.position, direction, direction, radiance, 1.0, pdf_uniform_cone(light.cone), 0u, true, false, false);
}

fn spot_emission_pdf(light: LightSource, direction: vec3<f32>) -> EmissionPdf {
    return EmissionPdf(1.0, select(0.0, pdf_uniform_cone(light.cone), dot(direction, light.direction) > light.cos_outer));
}
