// Spot lights: a point light whose intensity falls linearly in angle from its beam to its cutoff (Mitsuba's `spot`).
//! include "light_sample.wgsl"

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
