// The sun: a distant disc of uniform radiance, sampled uniformly in its cone; sample beside pdf.
//! include "light_sample.wgsl"
//! include "sampling.wgsl"

// Whether `direction` (towards the sky) lies in the sun's disc. Compared through the squared sine
// of its angle to the axis, which f32 keeps to 7 digits where the cosine of a 0.27 degree angle
// keeps 3 (light.cone = 1 - cos of the disc's angular radius, from float64 on the host).
fn sun_contains(light: LightSource, direction: vec3<f32>) -> bool {
    let off_axis = cross(direction, light.direction);
    return dot(direction, light.direction) < 0.0 && dot(off_axis, off_axis) <= light.cone * (2.0 - light.cone);
}

fn sun_pdf(light: LightSource, direction: vec3<f32>) -> f32 {
    return select(0.0, 1.0 / (TWO_PI * light.cone), sun_contains(light, direction));
}

fn sun_escaped_radiance(light: LightSource, direction: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), light.emission, sun_contains(light, direction));
}

// Uniform in the cone around -light.direction: cos theta uniform in [1 - cone, 1], written through
// 1 - cos theta = u cone so that the sine keeps its digits.
fn sun_sample(light: LightSource, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let one_minus_cos = u.x * light.cone;
    let sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    let phi = TWO_PI * u.y;
    let local = vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), 1.0 - one_minus_cos);
    let direction = to_world(shading_frame(-light.direction), local);
    return LightSample(p, -direction, light.emission, 0u, 1.0 / (TWO_PI * light.cone), direction, true, false);
}
