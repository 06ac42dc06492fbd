// Next-event estimation's light sampler: an emissive triangle by power (alias table), a point
// uniform on it; sample_light beside pdf_light_area, which must agree with it.
//! include "scene_bindings.wgsl"
//! include "constants.wgsl"

@group(0) @binding(6) var<storage, read> lights: array<Light>;

// Rec. 709 luminance, the same weights as wgputrace/render/lights.py's LUMINANCE_WEIGHTS.
const LUMINANCE_WEIGHTS: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

struct LightSample {
    position: vec3<f32>,
    // unit geometric normal of the light triangle; emitters shine from both sides
    normal: vec3<f32>,
    radiance: vec3<f32>,
    triangle: u32,
    pdf_area: f32,
}

fn luminance(color: vec3<f32>) -> f32 {
    return dot(color, LUMINANCE_WEIGHTS);
}

// Triangles are chosen with probability area x luminance / total, points uniformly (1 / area):
// the area density of every light point is its luminance over the total, whatever the triangle.
fn pdf_light_area(radiance: vec3<f32>) -> f32 {
    return luminance(radiance) / frame.light_weight_total;
}

fn sample_light(u_select: vec2<f32>, u_point: vec2<f32>) -> LightSample {
    let slot = min(u32(u_select.x * f32(frame.light_count)), frame.light_count - 1u);
    let entry = lights[slot];
    let index = select(lights[entry.alias_index].triangle, entry.triangle, u_select.y < entry.threshold);
    let triangle = triangles[index];
    // uniform on the triangle: sqrt warps the first coordinate so area is preserved
    let s = sqrt(u_point.x);
    let position = triangle.v0 * (1.0 - s) + triangle.v1 * (s * (1.0 - u_point.y)) + triangle.v2 * (s * u_point.y);
    let normal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
    let radiance = materials[triangle.material].color;
    return LightSample(position, normal, radiance, index, pdf_light_area(radiance));
}

// Area density to solid-angle density, seen from a point `distance` away at cosine `cos_light`.
fn area_to_solid_angle(pdf_area: f32, distance_squared: f32, cos_light: f32) -> f32 {
    return pdf_area * distance_squared / cos_light;
}
