// Shading frames and the warps that sample directions in them; every sample_x sits beside its pdf_x.
//! include "common/constants.wgsl"

struct ShadingFrame {
    tangent: vec3<f32>,
    bitangent: vec3<f32>,
    normal: vec3<f32>,
}

// Orthonormal basis around a unit normal without branches on near-axis normals (Duff et al. 2017).
fn shading_frame(n: vec3<f32>) -> ShadingFrame {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return ShadingFrame(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
        n,
    );
}

fn to_local(frame: ShadingFrame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, frame.tangent), dot(v, frame.bitangent), dot(v, frame.normal));
}

fn to_world(frame: ShadingFrame, v: vec3<f32>) -> vec3<f32> {
    return v.x * frame.tangent + v.y * frame.bitangent + v.z * frame.normal;
}

// Uniform point on the unit disk: the radius's square uniform, phi uniform.
fn sample_uniform_disk(u: vec2<f32>) -> vec2<f32> {
    let r = sqrt(u.x);
    let phi = TWO_PI * u.y;
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

fn pdf_uniform_disk() -> f32 {
    return INV_PI;
}

// Cosine-weighted direction on the +z hemisphere: a uniform disk point lifted to the hemisphere.
fn sample_cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(sample_uniform_disk(u), sqrt(max(0.0, 1.0 - u.x)));
}

fn pdf_cosine_hemisphere(cos_theta: f32) -> f32 {
    return max(cos_theta, 0.0) * INV_PI;
}

// Uniform direction on the unit sphere: z uniform in [-1, 1] (Archimedes), phi uniform.
fn sample_uniform_sphere(u: vec2<f32>) -> vec3<f32> {
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = TWO_PI * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

fn pdf_uniform_sphere() -> f32 {
    return 0.25 * INV_PI;
}

// Uniform direction in the cone of directions within an angle theta_max of +z, given as
// 1 - cos(theta_max): cos theta uniform in [cos theta_max, 1], written through 1 - cos theta = u
// (1 - cos theta_max) so that the sine of a narrow cone (the sun's) keeps its digits.
fn sample_uniform_cone(u: vec2<f32>, one_minus_cos_max: f32) -> vec3<f32> {
    let one_minus_cos = u.x * one_minus_cos_max;
    let sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    let phi = TWO_PI * u.y;
    return vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), 1.0 - one_minus_cos);
}

fn pdf_uniform_cone(one_minus_cos_max: f32) -> f32 {
    return 1.0 / (TWO_PI * one_minus_cos_max);
}

// Uniform point on the unit disk by Shirley and Chiu's concentric map: squares to rings, so
// neighbouring (stratified) samples stay neighbours on the disk; (0.5, 0.5) is its centre.
fn sample_concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let offset = 2.0 * u - 1.0;
    if all(offset == vec2<f32>(0.0)) {
        return vec2<f32>(0.0);
    }
    if abs(offset.x) > abs(offset.y) {
        let phi = 0.25 * PI * (offset.y / offset.x);
        return offset.x * vec2<f32>(cos(phi), sin(phi));
    }
    let phi = 0.5 * PI - 0.25 * PI * (offset.x / offset.y);
    return offset.y * vec2<f32>(cos(phi), sin(phi));
}
