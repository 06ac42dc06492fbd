// normal_mapped: the shading normal bent by a tangent-space normal from a texel (glTF normalTexture).
//
// The mapped normal only replaces the shading normal: the geometric normal keeps deciding sides
// and ray offsets, and shading_weight applies to it as to any shading normal, so bumps cannot leak
// light through the surface.

// Below this a vector has no reliable direction in f32 (a tangent along the normal, a zero texel).
const NORMAL_MAP_MIN_LENGTH: f32 = 1e-6;

// The texel's RGB in [0, 1] encodes a unit vector in the frame (tangent, bitangent, normal), +Y up
// the image; glTF scales its x and y by normal_scale (`scale`) before normalising. The frame is
// built from the interpolated shading normal and corner tangent (corner_tangents: the file's
// TANGENT or MikkTSpace's), bitangent = cross(normal, tangent) * w as glTF defines it. Where no
// frame or normal can be trusted it returns the unmapped shading normal, which shading_normal has
// already checked: a tangent along the normal or zero (degenerate texture coordinates), a texel that
// cancels to zero, a mapped normal below the geometric surface or one that hides the viewer (as
// shading_normal keeps the geometric normal between the two horizons).
fn normal_mapped(shading: vec3<f32>, tangent: vec4<f32>, texel: vec3<f32>, scale: f32, geometric: vec3<f32>, towards_viewer: vec3<f32>) -> vec3<f32> {
    // interpolation bends corner tangents away from the interpolated normal: Gram-Schmidt
    let t_unnormalised = tangent.xyz - shading * dot(shading, tangent.xyz);
    let t_length = length(t_unnormalised);
    // NaN too
    if !(t_length > NORMAL_MAP_MIN_LENGTH) {
        return shading;
    }
    let t = t_unnormalised / t_length;
    let b = cross(shading, t) * select(1.0, -1.0, tangent.w < 0.0);
    let m = vec3<f32>((texel.xy * 2.0 - 1.0) * scale, texel.z * 2.0 - 1.0);
    let n_unnormalised = m.x * t + m.y * b + m.z * shading;
    let n_length = length(n_unnormalised);
    if !(n_length > NORMAL_MAP_MIN_LENGTH) {
        return shading;
    }
    let n = n_unnormalised / n_length;
    if dot(n, geometric) <= 0.0 || dot(n, towards_viewer) * dot(geometric, towards_viewer) <= 0.0 {
        return shading;
    }
    return n;
}
