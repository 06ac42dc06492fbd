// Where a point lies on a triangle, for interpolating what its corners carry (normals, texture coordinates).

// The barycentric weights (b1, b2) of corners v1 and v2 at `p` (v0's is 1 - b1 - b2), clamped so
// that a point off the triangle by rounding still gets a convex combination. NaN for a zero-area
// triangle (its determinant is 0): callers check what they interpolate.
fn triangle_barycentric(triangle: Triangle, p: vec3<f32>) -> vec2<f32> {
    let e1 = triangle.v1 - triangle.v0;
    let e2 = triangle.v2 - triangle.v0;
    let d = p - triangle.v0;
    let d11 = dot(e1, e1);
    let d12 = dot(e1, e2);
    let d22 = dot(e2, e2);
    let d1 = dot(d, e1);
    let d2 = dot(d, e2);
    let determinant = d11 * d22 - d12 * d12;
    let b1 = clamp((d22 * d1 - d12 * d2) / determinant, 0.0, 1.0);
    let b2 = clamp((d11 * d2 - d12 * d1) / determinant, 0.0, 1.0 - b1);
    return vec2<f32>(b1, b2);
}
