// Uniform sampling of the solid angle a triangle subtends (Arvo 1995, as pbrt-v4 writes it), beside its area.
//! include "common/constants.wgsl"

// Solid angle of the spherical triangle with unit corners a, b, c (Van Oosterom and Strackee
// 1983): no pi to subtract from a sum of angles, so small triangles keep their precision.
fn spherical_triangle_area(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    return 2.0 * atan2(abs(dot(a, cross(b, c))), 1.0 + dot(a, b) + dot(a, c) + dot(b, c));
}

// Angle between unit vectors, accurate near 0 and pi where acos(dot) is not.
fn angle_between(u: vec3<f32>, v: vec3<f32>) -> f32 {
    if dot(u, v) < 0.0 {
        return PI - 2.0 * asin(min(length(u + v) * 0.5, 1.0));
    }
    return 2.0 * asin(min(length(v - u) * 0.5, 1.0));
}

// `w` with its component along the unit vector `axis` removed, normalized.
fn orthogonal_direction(w: vec3<f32>, axis: vec3<f32>) -> vec3<f32> {
    return normalize(w - dot(w, axis) * axis);
}

// A direction uniform in the solid angle `area` (spherical_triangle_area(a, b, c)) of the
// spherical triangle a, b, c: the first coordinate picks the sub-triangle a, b, c' of area
// u.x * area, the second a point on the arc from b to c' so that area stays uniform. The
// sub-triangle's angle at a is pi - alpha + u.x * area (its angles sum to pi + u.x * area), written
// through alpha - u.x * area so that no pi is added and subtracted.
fn sample_spherical_triangle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, area: f32, u: vec2<f32>) -> vec3<f32> {
    let n_ab = normalize(cross(a, b));
    let n_ca = normalize(cross(c, a));
    let alpha = angle_between(n_ab, -n_ca);
    let cos_alpha = cos(alpha);
    let sin_alpha = sin(alpha);
    let rest = alpha - u.x * area;
    let sin_phi = sin(rest);
    let cos_phi = -cos(rest);
    let k1 = cos_phi + cos_alpha;
    let k2 = sin_phi - sin_alpha * dot(a, b);
    let cos_b = clamp((k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha), -1.0, 1.0);
    let c_prime = cos_b * a + sqrt(max(1.0 - cos_b * cos_b, 0.0)) * orthogonal_direction(c, a);
    let cos_theta = 1.0 - u.y * (1.0 - dot(c_prime, b));
    return cos_theta * b + sqrt(max(1.0 - cos_theta * cos_theta, 0.0)) * orthogonal_direction(c_prime, b);
}
