// sample_light beside pdf_light: direct lighting's light sampler, a light by power, then a point on it.
// One alias table (light_table) holds every light: emissive triangles, light sources and the
// environment. A triangle's point is uniform in its solid angle (uniform in area for tiny or huge
// ones); the other kinds sample in their own files, through the generated dispatch.
//! include "geometry/scene_bindings.wgsl"
//! include "common/constants.wgsl"
//! include "sampling/spherical_triangle.wgsl"
// material_emitted: a light triangle's radiance, as its material kind defines it
//! include "generated/materials.wgsl"
// surface_emission and surface_light_density: light emitted through a material's texture record
// (Principled's emission: emission_hook)
//! include "generated/emission.wgsl"
// is_light_source and sample_light_source: the scene's other lights (light_dispatch)
//! include "generated/lights.wgsl"

// Light triangles subtending solid angles in this range (steradians) are sampled uniformly in solid
// angle (sample_spherical_triangle); outside it, uniformly in area. Below the minimum the sampler's
// f32 trigonometry loses digits and a triangle that small looks alike from all its points, so
// area sampling is as good; above the maximum (nearly a hemisphere, from right beside a triangle)
// the arcs degenerate: pbrt-v4's MinSphericalSampleArea and MaxSphericalSampleArea. An override,
// so that bench.error_breakdown can measure area sampling alone (a minimum above 4 pi).
override SPHERICAL_SAMPLING_MIN_SOLID_ANGLE: f32 = 3e-4;
const SPHERICAL_SAMPLING_MAX_SOLID_ANGLE: f32 = 6.22;

// Rec. 709 luminance, the same weights as the host's LUMINANCE_WEIGHTS.
const LUMINANCE_WEIGHTS: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

fn luminance(color: vec3<f32>) -> f32 {
    return dot(color, LUMINANCE_WEIGHTS);
}

fn light_triangle_solid_angle(p: vec3<f32>, triangle: Triangle) -> f32 {
    return spherical_triangle_area(normalize(triangle.v0 - p), normalize(triangle.v1 - p), normalize(triangle.v2 - p));
}

fn samples_solid_angle(solid_angle: f32) -> bool {
    return solid_angle >= SPHERICAL_SAMPLING_MIN_SOLID_ANGLE && solid_angle <= SPHERICAL_SAMPLING_MAX_SOLID_ANGLE;
}

// The light table's weight per unit area of light triangle `triangle_index` (light_table):
// the luminance of its material kind's radiance, or of what it emits through a texture record.
fn light_density(triangle_index: u32, triangle: Triangle) -> f32 {
    return luminance(material_emitted(materials[triangle.material])) + surface_light_density(triangle_index);
}

// Density per steradian, seen from `p`, with which sample_light picks the point of light triangle
// `triangle` (number `triangle_index`) at squared distance `distance_squared` and cosine `cos_light`. Triangles are chosen
// with probability area x light_density / total (the total over every light, each weighed in the
// same units); within the triangle the point is uniform in solid angle (1 / solid angle) or in
// area (1 / area, converted to solid angle).
fn pdf_light(p: vec3<f32>, triangle_index: u32, triangle: Triangle, distance_squared: f32, cos_light: f32) -> f32 {
    let per_area = light_density(triangle_index, triangle) / frame.light_weight_total;
    let solid_angle = light_triangle_solid_angle(p, triangle);
    if samples_solid_angle(solid_angle) {
        return per_area * (0.5 * length(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0))) / solid_angle;
    }
    return per_area * distance_squared / cos_light;
}

// The light table's word of a light drawn by power: slot u_select.x, kept below its threshold,
// else its alias. Light paths (sample_emission) choose their light by the same draw.
fn choose_light(u_select: vec2<f32>) -> u32 {
    let slot = min(u32(u_select.x * f32(frame.light_count)), frame.light_count - 1u);
    let entry = lights[slot];
    return select(lights[entry.alias_index].triangle, entry.triangle, u_select.y < entry.threshold);
}

// Uniform on the triangle: sqrt warps the first coordinate so area is preserved.
fn uniform_triangle_point(triangle: Triangle, u: vec2<f32>) -> vec3<f32> {
    let s = sqrt(u.x);
    return triangle.v0 * (1.0 - s) + triangle.v1 * (s * (1.0 - u.y)) + triangle.v2 * (s * u.y);
}

fn sample_light(p: vec3<f32>, u_select: vec2<f32>, u_point: vec2<f32>) -> LightSample {
    return sample_chosen_light(choose_light(u_select), p, u_point);
}

// sample_light once it chose the light table's word `index`: a point of that light, seen from `p`,
// its density including the light's choice.
fn sample_chosen_light(index: u32, p: vec3<f32>, u_point: vec2<f32>) -> LightSample {
    if is_light_source(index) {
        return sample_light_source(index, p, u_point);
    }
    let triangle = scene_triangle(index);
    let normal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
    let a = normalize(triangle.v0 - p);
    let b = normalize(triangle.v1 - p);
    let c = normalize(triangle.v2 - p);
    let solid_angle = spherical_triangle_area(a, b, c);
    var position: vec3<f32>;
    if samples_solid_angle(solid_angle) {
        let direction = sample_spherical_triangle(a, b, c, solid_angle, u_point);
        // where the sampled direction meets the triangle's plane
        position = p + direction * (dot(triangle.v0 - p, normal) / dot(direction, normal));
    } else {
        position = uniform_triangle_point(triangle, u_point);
    }
    let to_light = position - p;
    let distance_squared = dot(to_light, to_light);
    let cos_light = abs(dot(normal, to_light)) / sqrt(distance_squared);
    let radiance = material_emitted(materials[triangle.material]) + surface_emission(triangle.material, index, triangle, position, to_light);
    let pdf = pdf_light(p, index, triangle, distance_squared, cos_light);
    return LightSample(position, normal, radiance, index, pdf, vec3<f32>(0.0), false, false);
}
