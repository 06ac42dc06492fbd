// check_weight_sums: the bidirectional kernel's check of its own MIS weights (BDPT_CHECK_WEIGHT_SUMS).
// Veach's weights of the strategies that can sample a path sum to one for that path, whatever
// stand-in densities they share (MisSums); a density one strategy computes differently from how the
// others see it breaks the sum (test_bdpt_weights).

// A vertex of the camera subpath being checked: the camera subpath's MIS sums on reaching it and
// whether it scattered towards the next vertex as a delta. Every direction of the check runs
// between the path's points, and every density is evaluated along them (scattering), on both
// subpaths alike: the kernel's sampled rays leave from moved origins, which across a short edge
// into a corner turn a direction enough to move the sum by 1e-3 (an error of the kernel's f32
// geometry, not of its weights).
struct CheckedVertex {
    vertex: SurfaceVertex,
    sums: MisSums,
    delta: bool,
}

// The largest deviation |sum - 1| over the paths checked, how many paths, how many weights summed.
struct WeightSumCheck {
    deviation: f32,
    paths: f32,
    strategies: f32,
}

// x_1 .. x_m of the camera subpath: a checked path of m + 1 edges (at most max_depth) ends beyond x_m
var<private> checked_vertices: array<CheckedVertex, BDPT_LIGHT_VERTICES>;
// the lens sample of the camera ray checked: its point on the lens is the path's camera vertex
var<private> camera_lens: vec2<f32>;

// The start a light subpath would have had at the path's light end, travelling to x_m.
fn end_emission(end: NextEventSample) -> EmissionSample {
    let direction = -end.direction;
    let light = end.light;
    if light.distant && light.delta {
        // only the flags count (emission_mis_sums: the scene's disc)
        return EmissionSample(vec3<f32>(0.0), direction, direction, light.radiance, 1.0, 1.0, end.word, false, true, true);
    }
    if light.distant {
        let pdf = emission_pdf_distant(direction);
        return EmissionSample(vec3<f32>(0.0), direction, direction, light.radiance, pdf.position, pdf.direction, end.word, false, false, true);
    }
    let pdf = emission_pdf(end.word, direction);
    let normal = select(light.normal, -light.normal, dot(light.normal, direction) < 0.0);
    return EmissionSample(light.position, normal, direction, light.radiance, pdf.position, pdf.direction, end.word, light.delta, false, false);
}

// The light end of a camera subpath that found the emission of triangle `triangle_index` at `p`
// along `direction` (unit) from `origin`, as next-event estimation would have sampled it.
fn emission_hit_end(p: vec3<f32>, triangle_index: u32, geometric: vec3<f32>, emitted: vec3<f32>, origin: vec3<f32>, direction: vec3<f32>) -> NextEventSample {
    let light = LightSample(p, geometric, emitted, triangle_index, 1.0, vec3<f32>(0.0), false, false);
    return NextEventSample(light, triangle_index, direction, length(p - origin), abs(dot(geometric, direction)));
}

// The light end of a camera subpath that left the scene along `direction` (unit).
fn escaped_end(direction: vec3<f32>, radiance: vec3<f32>) -> NextEventSample {
    let light = LightSample(vec3<f32>(0.0), -direction, radiance, 0u, 1.0, direction, true, false);
    return NextEventSample(light, ENVIRONMENT_LIGHT, direction, FLOAT_MAX, 1.0);
}

// The weights of every strategy that can sample the path camera, x_1 .. x_m (checked_vertices),
// `end`: (their sum, how many). x_m scatters towards the end as a delta where `last_delta`.
fn checked_path_weights(m: u32, end: NextEventSample, last_delta: bool) -> vec2<f32> {
    let x_m = checked_vertices[m - 1u];
    let last = scattering(x_m.vertex, end.direction);
    var sum = 0.0;
    var count = 0.0;
    // s = 0: the camera subpath scatters from x_m and finds the light
    if !end.light.delta {
        let scattered = mis_sums_after_scattering(x_m.sums, abs(dot(x_m.vertex.geometric, end.direction)), last.forward, last.reverse, last_delta);
        if end.light.distant {
            sum += escaped_emission_weight(scattered, end.direction);
        } else {
            let found = mis_sums_at_hit(scattered, end.distance, end.cos_light, false);
            sum += triangle_emission_weight(found, end.word, scene_triangle(end.word), end.direction);
        }
        count += 1.0;
    }
    let emitted = end_emission(end);
    // a black emitter outside the light table: no light sample or light path starts there
    if !(emitted.pdf_position > 0.0) {
        return vec2<f32>(sum, count);
    }
    // s = 1: next-event estimation from x_m
    if connectible(x_m.vertex) && !last_delta {
        sum += next_event_mis(x_m.vertex, x_m.sums, end, last);
        count += 1.0;
    }
    // s = j + 1 >= 2: the light subpath's vertex y_j at x_{m + 1 - j} (index i) joined to x_i, or
    // for j = m to the camera
    var sums = emission_mis_sums(emitted, end.cos_light);
    for (var j = 1u; j <= m; j++) {
        let i = m - j;
        let here = checked_vertices[i];
        let p = here.vertex.position;
        var towards = end.direction;
        var distance = end.distance;
        if j > 1u {
            let back = checked_vertices[i + 1u].vertex.position - p;
            distance = length(back);
            towards = back * inverseSqrt(dot(back, back));
        }
        let y = vertex_at(p, here.vertex.triangle_index, scene_triangle(here.vertex.triangle_index), towards, true);
        sums = mis_sums_at_hit(sums, distance, abs(dot(y.geometric, towards)), j == 1u && end.light.distant);
        let delta_here = select(here.delta, last_delta, j == 1u);
        let joins = connectible(y) && !delta_here;
        if i == 0u {
            // light tracing reaches the camera at the camera ray's own lens point
            let camera = camera_connection(p, camera_lens);
            let to_camera = camera.position - p;
            let distance_squared = dot(to_camera, to_camera);
            let direction = to_camera * inverseSqrt(distance_squared);
            let light_side = scattering(y, direction);
            if joins && camera.seen && any(light_side.value != vec3<f32>(0.0)) {
                sum += camera_connection_mis(y, sums, light_side, camera.pdf, direction, distance_squared);
                count += 1.0;
            }
            break;
        }
        let x = checked_vertices[i - 1u];
        let to_y = p - x.vertex.position;
        let distance_squared = dot(to_y, to_y);
        let direction = to_y * inverseSqrt(distance_squared);
        let camera_side = scattering(x.vertex, direction);
        let light_side = scattering(y, -direction);
        if joins && connectible(x.vertex) && !x.delta && any(camera_side.value != vec3<f32>(0.0)) && any(light_side.value != vec3<f32>(0.0)) {
            let light_vertex = LightVertex(y, vec3<f32>(0.0), sums, j);
            sum += vertex_connection_mis(x.vertex, x.sums, light_vertex, camera_side, light_side, direction, distance_squared);
            count += 1.0;
        }
        // on to x_i, the light subpath's next vertex
        sums = mis_sums_after_scattering(sums, abs(dot(y.geometric, direction)), light_side.forward, light_side.reverse, delta_here);
    }
    return vec2<f32>(sum, count);
}

fn with_checked_path(check: WeightSumCheck, weights: vec2<f32>) -> WeightSumCheck {
    return WeightSumCheck(max(check.deviation, abs(weights.x - 1.0)), check.paths + 1.0, check.strategies + weights.y);
}

// Walks a camera subpath as the kernel does and closes full paths as the kernel's strategies find
// them: emission hit, a next-event light sample, distant light on leaving. For each such path it
// evaluates the weight of every strategy (s, t) that could have sampled that same path, from both
// ends, with the kernel's own weight functions, and sums them.
//
// One camera subpath from `camera`, made from lens sample `lens` (BSDF sampling as
// trace_camera_subpath, without roulette) and every path it closes checked: (largest |sum - 1|,
// paths, weights summed) as a colour. A NaN sum makes the colour non-finite, which the
// accumulation counts.
fn check_weight_sums(camera: Ray, lens: vec2<f32>) -> vec3<f32> {
    camera_lens = lens;
    var check = WeightSumCheck(0.0, 0.0, 0.0);
    var ray = camera;
    var skip_triangle = NO_TRIANGLE;
    var sums = camera_mis_sums(camera_ray_density(camera));
    for (var depth = 1u; ; depth++) {
        let hit = closest_hit(ray, FLOAT_MAX, skip_triangle);
        if hit.triangle == NO_TRIANGLE {
            if HAS_ESCAPED_LIGHT && depth >= 2u {
                let radiance = escaped_light(ray.direction, false, false, 0.0);
                let previous = checked_vertices[depth - 2u];
                if any(radiance > vec3<f32>(0.0)) {
                    check = with_checked_path(check, checked_path_weights(depth - 1u, escaped_end(ray.direction, radiance), previous.delta));
                }
            }
            break;
        }
        let triangle = scene_triangle(hit.triangle);
        let p = ray.origin + hit.t * ray.direction;
        let previous = checked_vertices[max(depth, 2u) - 2u];
        let previous_point = select(previous.vertex.position, camera.origin, depth == 1u);
        let edge = p - previous_point;
        let distance = length(edge);
        // as the connections (connect_vertices) make their directions, bit for bit
        let direction = edge * inverseSqrt(dot(edge, edge));
        let v = vertex_at(p, hit.triangle, triangle, -direction, false);
        if depth >= 2u {
            let scattered = scattering(previous.vertex, direction);
            sums = mis_sums_after_scattering(previous.sums, abs(dot(previous.vertex.geometric, direction)), scattered.forward, scattered.reverse, previous.delta);
        }
        sums = mis_sums_at_hit(sums, distance, abs(dot(v.geometric, direction)), depth == 1u && CAMERA_PARALLEL);
        let emitted = material_emitted(v.material) + surface_emission(triangle.material, hit.triangle, triangle, v.position, ray.direction);
        if depth >= 2u && any(emitted > vec3<f32>(0.0)) {
            let end = emission_hit_end(v.position, hit.triangle, v.geometric, emitted, previous_point, direction);
            check = with_checked_path(check, checked_path_weights(depth - 1u, end, previous.delta));
        }
        if !material_reflects(v.material) || depth >= frame.max_depth {
            break;
        }
        checked_vertices[depth - 1u] = CheckedVertex(v, sums, false);
        if connectible(v) && frame.light_count != 0u {
            let sample = sample_next_event(v);
            let s = scattering(v, sample.direction);
            if sample.light.pdf > 0.0 && sample.cos_light > COS_MIN && any(s.value != vec3<f32>(0.0)) && any(sample.light.radiance > vec3<f32>(0.0)) {
                check = with_checked_path(check, checked_path_weights(depth, sample, false));
            }
        }
        let next = sample_scattering(v);
        if next.forward <= 0.0 {
            break;
        }
        checked_vertices[depth - 1u].delta = next.delta;
        ray = vertex_ray(v, next.direction);
        skip_triangle = hit.triangle;
    }
    return vec3<f32>(check.deviation, check.paths, check.strategies);
}
