// The strategies that join a camera subpath to light, each with its MIS weight and its own shadow ray.
// Next-event estimation (s = 1), a connection to a stored light vertex (s >= 2, t >= 2) and light
// tracing's connection to the camera (t = 1); the camera subpath's shadow rays are queued.
//! include "integrators/bdpt/vertex.wgsl"
//! include "integrators/bdpt/shadow_queue.wgsl"
//! include "integrators/bdpt/mis_weight.wgsl"
//! include "generated/camera.wgsl"
//! include "lights/light_path_sampler.wgsl"

// A vertex of the light subpath kept for connections: where it is, what the light subpath carries
// there (throughput, MIS sums) and how many edges lead to it from the light.
struct LightVertex {
    vertex: SurfaceVertex,
    throughput: vec3<f32>,
    sums: MisSums,
    edges: u32,
}

// The segment between the vertices' points (each moved off its surface).
fn segment_shadow_ray(a: SurfaceVertex, b: SurfaceVertex, direction: vec3<f32>) -> ShadowRay {
    let start = vertex_ray(a, direction).origin;
    let end = vertex_ray(b, -direction).origin;
    let distance = length(end - start);
    return ShadowRay(Ray(start, (end - start) / distance), distance * SHADOW_RAY_SHORTENING, a.triangle_index);
}

// The way from `x` to the sampled light (towards `direction`): as the path tracer's light_occluded, aimed from
// the moved origin up to the light point, or to infinity.
fn light_shadow_ray(x: SurfaceVertex, light: LightSample, direction: vec3<f32>) -> ShadowRay {
    let origin = vertex_ray(x, direction).origin;
    if light.distant {
        return ShadowRay(Ray(origin, direction), FLOAT_MAX, x.triangle_index);
    }
    let shadow = light.position - origin;
    let shadow_distance = length(shadow);
    return ShadowRay(Ray(origin, shadow / shadow_distance), shadow_distance * SHADOW_RAY_SHORTENING, x.triangle_index);
}

// The MIS sums a light subpath starts with from `emitted` (MisSums' stand-in densities:
// the distant lights' mixture, a directional light's scene disc).
fn emission_mis_sums(emitted: EmissionSample, cos_light: f32) -> MisSums {
    if emitted.distant && emitted.delta_direction {
        return MisSums(mis(bdpt_distant_disk_area()), 0.0);
    }
    if emitted.distant {
        return light_mis_sums(distant_emission(-emitted.direction).pdf, emitted.pdf_position * emitted.pdf_direction, 1.0, false);
    }
    return light_mis_sums(emitted.pdf_position, emitted.pdf_position * emitted.pdf_direction, cos_light, emitted.delta_position);
}

// The weight of emission that camera ray `direction` found at light triangle `triangle_index` (s = 0).
fn triangle_emission_weight(sums: MisSums, triangle_index: u32, triangle: Triangle, direction: vec3<f32>) -> f32 {
    let pdf = emission_pdf_triangle(triangle_index, triangle, -direction);
    return emission_hit_weight(sums, pdf.position, pdf.position * pdf.direction);
}

// The weight of the distant lights seen by a ray escaping along `direction` (s = 0).
fn escaped_emission_weight(sums: MisSums, direction: vec3<f32>) -> f32 {
    let pdf = emission_pdf_distant(-direction);
    return emission_hit_weight(sums, distant_emission(direction).pdf, pdf.position * pdf.direction);
}

// One light sample for next-event estimation from `x`, as the path tracer draws it, with the light
// table word of the light it chose (sample_light leaves a light source's out of LightSample), the
// unit `direction` towards it, its `distance` (distant lights: FLOAT_MAX) and the cosine there.
struct NextEventSample {
    light: LightSample,
    word: u32,
    direction: vec3<f32>,
    distance: f32,
    cos_light: f32,
}

fn sample_next_event(x: SurfaceVertex) -> NextEventSample {
    let u_select = sample_2d();
    let light = sample_light(x.position, u_select, sample_2d());
    var direction = light.direction;
    var distance = FLOAT_MAX;
    if !light.distant {
        let to_light = light.position - x.position;
        distance = length(to_light);
        direction = to_light * inverseSqrt(dot(to_light, to_light));
    }
    return NextEventSample(light, choose_light(u_select), direction, distance, abs(dot(light.normal, direction)));
}

// The next-event estimation weight of `sample` reaching `x`; `s`: x's scattering towards it.
fn next_event_mis(x: SurfaceVertex, sums: MisSums, sample: NextEventSample, s: Scattering) -> f32 {
    let light = sample.light;
    let direction = sample.direction;
    let cos_x = abs(dot(x.geometric, direction));
    if light.distant && light.delta {
        return next_event_weight(sums, 0.0, 1.0, cos_x / bdpt_distant_disk_area(), s.reverse);
    }
    if light.distant {
        let pdf = emission_pdf_distant(-direction);
        let direct = distant_emission(direction).pdf;
        return next_event_weight(sums, s.forward, direct, pdf.position * pdf.direction * cos_x / direct, s.reverse);
    }
    let distance_squared = sample.distance * sample.distance;
    // a point or spot light: next-event estimation picks its point with its selection probability
    // alone, a light path its direction with the density of the light's emission
    let pdf = emission_pdf(sample.word, -direction);
    if light.delta {
        return next_event_weight(sums, 0.0, 1.0, pdf.direction * cos_x / distance_squared, s.reverse);
    }
    let direct = pdf.position * distance_squared / sample.cos_light;
    return next_event_weight(sums, s.forward, direct, pdf.position * pdf.direction * cos_x / (direct * sample.cos_light), s.reverse);
}

// Next-event estimation from camera vertex `x` (s = 1, t = `t`): one light sample as the path
// tracer draws it, weighted, with its shadow ray.
fn next_event(x: SurfaceVertex, sums: MisSums, t: u32) -> Shadowed {
    let sample = sample_next_event(x);
    // as in the path tracer's direct_light: an environment sample's density may round to 0
    if !(sample.light.pdf > 0.0) {
        return nothing_shadowed();
    }
    // NaN too: a point light at the receiving point has no direction
    if !(sample.cos_light > COS_MIN) {
        return nothing_shadowed();
    }
    let s = scattering(x, sample.direction);
    let weight = strategy_weight(1u, t, next_event_mis(x, sums, sample, s));
    if all(s.value == vec3<f32>(0.0)) || weight == 0.0 {
        return nothing_shadowed();
    }
    return Shadowed(light_shadow_ray(x, sample.light, sample.direction), s.value * sample.light.radiance * (weight / sample.light.pdf));
}

// The weight of joining camera vertex `x` (its subpath's `sums`, scattering `camera_side` towards
// `y`) to light vertex `y` (scattering `light_side` back), `direction` from x to y.
fn vertex_connection_mis(x: SurfaceVertex, sums: MisSums, y: LightVertex, camera_side: Scattering, light_side: Scattering, direction: vec3<f32>, distance_squared: f32) -> f32 {
    let cos_x = abs(dot(x.geometric, direction));
    let cos_y = abs(dot(y.vertex.geometric, direction));
    let light_term = mis_subpath_term(y.sums, light_side.reverse, camera_side.forward * cos_y / distance_squared);
    let camera_term = mis_subpath_term(sums, camera_side.reverse, light_side.forward * cos_x / distance_squared);
    return connection_weight(light_term, camera_term);
}

// Camera vertex `x` (t vertices with the camera) joined to light vertex `y` (s = y.edges + 1), with
// the shadow ray between them.
fn connect_vertices(x: SurfaceVertex, sums: MisSums, t: u32, y: LightVertex) -> Shadowed {
    let to_y = y.vertex.position - x.position;
    let distance_squared = dot(to_y, to_y);
    let direction = to_y * inverseSqrt(distance_squared);
    let camera_side = scattering(x, direction);
    let light_side = scattering(y.vertex, -direction);
    if all(camera_side.value == vec3<f32>(0.0)) || all(light_side.value == vec3<f32>(0.0)) {
        return nothing_shadowed();
    }
    let mis_weight = vertex_connection_mis(x, sums, y, camera_side, light_side, direction, distance_squared);
    let weight = strategy_weight(y.edges + 1u, t, mis_weight);
    return Shadowed(segment_shadow_ray(x, y.vertex, direction), y.throughput * camera_side.value * light_side.value * (weight / distance_squared));
}

// A splat of light tracing: what light vertex `y` sends through the camera into `pixel`.
struct Splat {
    pixel: u32,
    value: vec3<f32>,
}

// The falloff from the camera's density of a ray (camera_ray_density) to its density per unit
// area at a point at `distance_squared` (before the point's cosine): 1 / d^2 for rays from a
// point or lens, none for parallel rays, whose density is per unit area already.
fn camera_falloff(distance_squared: f32) -> f32 {
    return select(distance_squared, 1.0, CAMERA_PARALLEL);
}

// The weight of joining light vertex `y` (its subpath's `sums`, scattering `light_side` towards the
// camera along `direction`) to the camera, whose ray through it has density `camera_pdf`.
fn camera_connection_mis(y: SurfaceVertex, sums: MisSums, light_side: Scattering, camera_pdf: f32, direction: vec3<f32>, distance_squared: f32) -> f32 {
    let cos_y = abs(dot(y.geometric, direction));
    return connection_weight(mis_subpath_term(sums, light_side.reverse, camera_pdf * cos_y / camera_falloff(distance_squared)), 0.0);
}

// Light vertex `y` (s vertices with the light, carrying `throughput` and `sums`) joined to the
// camera (t = 1) at lens sample `lens`: the contribution to the pixel it lands in, zero where
// unseen or blocked.
fn connect_to_camera(y: SurfaceVertex, throughput: vec3<f32>, sums: MisSums, s: u32, lens: vec2<f32>) -> Splat {
    let none = Splat(0u, vec3<f32>(0.0));
    let camera = camera_connection(y.position, lens);
    if !camera.seen {
        return none;
    }
    let to_camera = camera.position - y.position;
    let distance_squared = dot(to_camera, to_camera);
    let direction = to_camera * inverseSqrt(distance_squared);
    let light_side = scattering(y, direction);
    if all(light_side.value == vec3<f32>(0.0)) {
        return none;
    }
    let weight = strategy_weight(s, 1u, camera_connection_mis(y, sums, light_side, camera.pdf, direction, distance_squared));
    if weight == 0.0 {
        return none;
    }
    let ray = vertex_ray(y, direction);
    if occluded(ray, length(camera.position - ray.origin) * SHADOW_RAY_SHORTENING, y.triangle_index) {
        return none;
    }
    return Splat(camera.pixel, throughput * light_side.value * (camera.pdf * weight / camera_falloff(distance_squared)));
}
