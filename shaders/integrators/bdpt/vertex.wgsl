// SurfaceVertex: a vertex of either subpath, how it scatters towards a direction and samples the next.
// On light subpaths it scatters by the adjoint BSDF.
//! include "materials/bsdf.wgsl"
//! include "geometry/ray.wgsl"

struct SurfaceVertex {
    position: vec3<f32>,
    // unit geometric normal (the triangle's), which measures areas and offsets rays
    geometric: vec3<f32>,
    // unit shading normal, the BSDF's frame
    shading: vec3<f32>,
    // unit, towards the previous vertex of its own subpath
    towards: vec3<f32>,
    material: Material,
    triangle_index: u32,
    // on a light subpath (importance flows towards `towards`' opposite)
    adjoint: bool,
}

fn triangle_normal(triangle: Triangle) -> vec3<f32> {
    return normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
}

// The vertex where `ray` hit `hit` (material resolved through its textures, shading normal as the
// path tracer takes it, seen from the ray's origin).
fn surface_vertex(ray: Ray, hit: Hit, triangle: Triangle, adjoint: bool) -> SurfaceVertex {
    return vertex_at(ray.origin + hit.t * ray.direction, hit.triangle, triangle, -ray.direction, adjoint);
}

// The vertex at `p` on triangle `triangle_index` reached from `towards` (unit).
fn vertex_at(p: vec3<f32>, triangle_index: u32, triangle: Triangle, towards: vec3<f32>, adjoint: bool) -> SurfaceVertex {
    let normal = triangle_normal(triangle);
    let material = vertex_colored(resolve_material(materials[triangle.material], triangle.material, triangle_index, triangle, p), triangle_index, triangle, p);
    let interpolated = shading_normal(triangle_index, triangle, p, normal, towards);
    let shading = mapped_normal(interpolated, material, triangle.material, triangle_index, triangle, p, normal, towards);
    return SurfaceVertex(p, normal, shading, towards, material, triangle_index, adjoint);
}

// Whether a connection may end at the vertex: glass and near-mirrors scatter as deltas for the
// weights (MisSums), so no strategy connects there.
fn connectible(v: SurfaceVertex) -> bool {
    return material_samples_lights(v.material);
}

// The shading normal at `v` seen from `viewer` (unit). The path tracer chooses it from the side
// towards the camera (shading_normal's silhouette rule, normal_mapped's rejection of a
// mapped normal facing away): on a camera subpath that is `towards`, on a light subpath the
// direction the path goes on in, known only once a connection or a sample chooses it. Every
// density of sampling a direction is taken in the frame the sampling vertex would have had,
// seen from where the path came from, so that both subpaths weigh a path alike.
fn shading_seen_from(v: SurfaceVertex, viewer: vec3<f32>) -> vec3<f32> {
    let triangle = scene_triangle(v.triangle_index);
    let interpolated = shading_normal(v.triangle_index, triangle, v.position, v.geometric, viewer);
    return mapped_normal(interpolated, v.material, triangle.material, v.triangle_index, triangle, v.position, v.geometric, viewer);
}

// |cos_s(wo)| |cos_g(wi)| / (|cos_g(wo)| |cos_s(wi)|) for wo = towards (the light's side) and
// wi = direction, with shading normal `shading`: 1 without shading normals.
fn adjoint_shading_correction(v: SurfaceVertex, shading: vec3<f32>, direction: vec3<f32>) -> f32 {
    let denominator = abs(dot(v.geometric, v.towards)) * abs(dot(shading, direction));
    if !(denominator > 0.0) {
        return 0.0;
    }
    return abs(dot(shading, v.towards)) * abs(dot(v.geometric, direction)) / denominator;
}

// What shading_weight keeps for the path through `v` continuing along `direction`, shaded with
// `shading`: the path tracer's rule, with viewer and light in the roles the path gives them.
fn vertex_shading_weight(v: SurfaceVertex, shading: vec3<f32>, direction: vec3<f32>) -> f32 {
    if v.adjoint {
        return shading_weight(shading, v.geometric, direction, v.towards) * adjoint_shading_correction(v, shading, direction);
    }
    return shading_weight(shading, v.geometric, v.towards, direction);
}

// The BSDF's frame at `v` about `shading` (surface_frame: along the tangent where anisotropy needs it).
fn vertex_frame(v: SurfaceVertex, shading: vec3<f32>) -> ShadingFrame {
    let triangle = scene_triangle(v.triangle_index);
    return surface_frame(shading, triangle.material, v.triangle_index, triangle, v.position, v.geometric);
}

// f |cos_g(direction)| of the path through `v` towards `direction`, shaded with `shading` (the
// normal seen from the camera's side).
fn bsdf_value(v: SurfaceVertex, shading: vec3<f32>, direction: vec3<f32>) -> vec3<f32> {
    let local = vertex_frame(v, shading);
    return bsdf_eval(v.material, to_local(local, v.towards), to_local(local, direction)) * vertex_shading_weight(v, shading, direction);
}

// The BSDF's density per steradian of sampling `to` at `v` for a path arriving from `from`, in the
// frame of `shading` (the normal seen from `from`).
fn direction_pdf(v: SurfaceVertex, shading: vec3<f32>, from_direction: vec3<f32>, to: vec3<f32>) -> f32 {
    let local = vertex_frame(v, shading);
    return bsdf_pdf(v.material, to_local(local, from_direction), to_local(local, to));
}

// Both subpaths estimate the path tracer's integrand: at each vertex f(wi, wo) |cos_s(wo)| times
// shading_weight, where wi points towards the camera's end and wo towards the light's (the BSDF in
// the shading frame, BsdfSample's convention). `scattering` returns that with the cosine on the
// side of `direction` instead, as a connection or a light subpath needs it: on a light subpath
// `direction` is wi, and by reciprocity f(wi, wo) |cos_s(wi)| = bsdf_eval(wo, wi); the factor
// |cos_s(wo)| |cos_g(wi)| / (|cos_g(wo)| |cos_s(wi)|) is Veach's adjoint correction for shading
// normals (thesis 5.3), which turns the shading cosine of wi into the geometric one the area
// measure's geometry term takes. A refraction's eta^2 scales radiance, not importance: light
// subpaths leave it out.
//
// f |cos_g(direction)| of the path through `v` towards `direction` (unit), and the BSDF's densities
// per steradian: `forward` of `direction` given `towards` (as this subpath would sample it),
// `reverse` of `towards` given `direction` (as the other subpath would).
struct Scattering {
    value: vec3<f32>,
    forward: f32,
    reverse: f32,
}

fn scattering(v: SurfaceVertex, direction: vec3<f32>) -> Scattering {
    let seen_from_direction = shading_seen_from(v, direction);
    let value = bsdf_value(v, select(v.shading, seen_from_direction, v.adjoint), direction);
    return Scattering(value, direction_pdf(v, v.shading, v.towards, direction), direction_pdf(v, seen_from_direction, direction, v.towards));
}

// The subpath's next direction from `v`: `weight` multiplies the throughput (f |cos_g| over the
// density, shading_weight and the adjoint correction applied), `eta` the refraction's ratio, the
// densities as in Scattering (a delta's: its lobe's probability both ways), `delta` also for vertices
// that cannot connect. A zero `forward` ends the subpath.
struct ScatteringSample {
    direction: vec3<f32>,
    weight: vec3<f32>,
    forward: f32,
    reverse: f32,
    eta: f32,
    delta: bool,
}

// The numbers sample_scattering draws.
const SCATTERING_DRAWS: u32 = 2u;

fn sample_scattering(v: SurfaceVertex) -> ScatteringSample {
    let local = vertex_frame(v, v.shading);
    let wi = to_local(local, v.towards);
    let u = sample_2d();
    let sample = bsdf_sample(v.material, wi, u, sample_1d());
    let direction = to_world(local, sample.direction);
    let seen_from_direction = shading_seen_from(v, direction);
    var weight = sample.weight * vertex_shading_weight(v, v.shading, direction);
    // a light subpath's vertex is shaded as seen from the direction it sampled; a delta lobe has
    // no value to evaluate in another frame and keeps its sampling frame's
    if v.adjoint && !sample.is_delta && any(seen_from_direction != v.shading) {
        weight = bsdf_value(v, seen_from_direction, direction) / sample.pdf;
    }
    if sample.pdf <= 0.0 || all(weight == vec3<f32>(0.0)) {
        return ScatteringSample(direction, vec3<f32>(0.0), 0.0, 0.0, 1.0, true);
    }
    if v.adjoint {
        weight /= sample.eta * sample.eta;
    }
    let delta = sample.is_delta || !connectible(v);
    let reverse = select(direction_pdf(v, seen_from_direction, direction, v.towards), sample.pdf, delta);
    return ScatteringSample(direction, weight, sample.pdf, reverse, sample.eta, delta);
}

// The ray leaving `v` along `direction`, moved off its triangle.
fn vertex_ray(v: SurfaceVertex, direction: vec3<f32>) -> Ray {
    let triangle = scene_triangle(v.triangle_index);
    return Ray(offset_ray_origin(v.position, v.geometric, direction, triangle.v0, triangle.v1, triangle.v2), direction);
}
