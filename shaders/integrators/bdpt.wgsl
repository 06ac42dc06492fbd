// The bidirectional path tracing megakernel (Veach 1997): a camera and a light subpath per pixel sample.
// Every strategy (s, t) between them is weighted by MIS; light tracing's splats are summed apart
// (splat) and added to the image by the renderer.
//! include "generated/acceleration.wgsl"
// camera_ray and what light tracing asks of the camera: the scene's camera kind (camera_hook)
//! include "generated/camera.wgsl"
//! include "camera/lens_sample.wgsl"
//! include "sampling/sampler.wgsl"
//! include "integrators/accumulate.wgsl"
//! include "integrators/loop_budget.wgsl"
//! include "integrators/bdpt/connect.wgsl"
//! include "integrators/bdpt/splat.wgsl"
//! include "integrators/bdpt/weight_sum_check.wgsl"
// guide_vertex and accumulate_guides: empty unless the denoiser's guides are compiled in (path_guides_hook)
//! include "generated/path_guides.wgsl"
// escaped_light and HAS_ESCAPED_LIGHT: what a ray leaving the scene sees (escaped_light_hook)
//! include "generated/escaped_light.wgsl"
// shading_normal and shading_weight: the geometric normal and 1 unless the scene has per-vertex
// normals (shading_normals_hook)
//! include "generated/shading_normals.wgsl"
// resolve_material and mapped_normal: the material and the shading normal as they are unless the
// scene has textures (textures_hook)
//! include "generated/textures.wgsl"
// vertex_colored: the material as it is unless the scene has vertex colours (vertex_colors_hook)
//! include "generated/vertex_colors.wgsl"
// bdpt_distant_disk_area and BDPT_LIGHT_VERTICES (bdpt_hook)
//! include "generated/bdpt.wgsl"
//! include "generated/bindings/pixels.wgsl"
//! include "generated/workgroup.wgsl"

// Russian roulette as the path tracer plays it (trace_path), on both subpaths: the light
// subpath's throughput carries the light's power, so there it judges the attenuation alone.
override RUSSIAN_ROULETTE_DEPTH: u32 = 3u;
override RUSSIAN_ROULETTE_MAX_SURVIVAL: f32 = 0.95;

// s counts the light subpath's vertices (the light's point included), t the camera subpath's (the
// camera included); a path of s + t vertices has s + t - 1 edges, at most max_depth (Mitsuba's
// count, as the path tracer's). s = 0: the camera subpath finds emission, a triangle's or, leaving
// the scene, the distant lights'; s = 1: next-event estimation (sample_light, the path tracer's
// light sampler: it samples triangles by solid angle and a fresh light per camera vertex, which
// the light subpath's first point cannot); s >= 2, t >= 2: connections; t = 1: light tracing. The
// light subpath's point on the light joined to the camera (s = 1, t = 1) is left out, as in pbrt:
// a camera ray finds it with weight 1.
//
// Debugging (pbrt's method, test_bdpt): with both set, only strategy
// (BDPT_ONLY_S, BDPT_ONLY_T) contributes, unweighted; each alone converges to the paths it samples.
const ALL_STRATEGIES: u32 = 0xFFFFFFFFu;
override BDPT_ONLY_S: u32 = ALL_STRATEGIES;
override BDPT_ONLY_T: u32 = ALL_STRATEGIES;

// Debugging (test_bdpt_weights): each pixel sample accumulates what check_weight_sums finds
// instead of radiance.
override BDPT_CHECK_WEIGHT_SUMS: bool = false;

fn strategy_weight(s: u32, t: u32, weight: f32) -> f32 {
    if BDPT_ONLY_S == ALL_STRATEGIES {
        return weight;
    }
    return select(0.0, 1.0, s == BDPT_ONLY_S && t == BDPT_ONLY_T);
}

// escaped_light weighs each distant light by this for the path tracer's MIS; here the sum of them
// is weighed against the other strategies at once (escaped_emission_weight).
fn escaped_weight(previous_sampled_lights: bool, previous_bsdf_pdf: f32, light_pdf: f32) -> f32 {
    return 1.0;
}

var<private> light_vertices: array<LightVertex, BDPT_LIGHT_VERTICES>;
var<private> light_vertex_count: u32;
// light tracing's splats, added to the image only once the sample is known complete (loop_budget_spent)
var<private> splats_pending: array<Splat, BDPT_LIGHT_VERTICES>;
var<private> splat_count: u32;
// the lens sample through which the light subpath's vertices splat (CAMERA_LENS; one per light
// subpath, drawn apart from the camera subpath's, as pbrt-v4's light tracing samples its own)
var<private> light_lens: vec2<f32>;

// Whether roulette ends a subpath at `edges`; `attenuation` is divided by the survival probability
// where it goes on (the caller divides its throughput alike).
struct Roulette {
    ends: bool,
    survival: f32,
}

// Whether roulette is played (and draws its number) at `edges`.
fn roulette_plays(edges: u32) -> bool {
    return edges >= RUSSIAN_ROULETTE_DEPTH;
}

fn play_roulette(edges: u32, attenuation: vec3<f32>) -> Roulette {
    if !roulette_plays(edges) {
        return Roulette(false, 1.0);
    }
    let survival = min(max_component(attenuation), RUSSIAN_ROULETTE_MAX_SURVIVAL);
    return Roulette(sample_1d() >= survival, survival);
}

// The numbers a light subpath draws at most: 3 for its light point and direction, then at each
// vertex that scatters (1 to max_depth - 2 edges from the light) 2 for the BSDF and 1 for roulette.
fn light_subpath_draw_budget() -> u32 {
    return 3u + 3u * (frame.max_depth - 2u);
}

// The light subpath, drawing light_subpath_draw_budget() numbers whatever its length: the camera
// subpath's k-th number then has the same dimension in every sample of a pixel, as in the path
// tracer, where the Sobol sampler stratifies each dimension over the samples (sample_1d). With
// the light subpath's length shifting them, glossy_through_glossy's MSE per sample was 1.3x
// (bench/README.md's log).
fn trace_light_subpath() {
    light_vertex_count = 0u;
    splat_count = 0u;
    if frame.light_count == 0u || frame.max_depth < 2u {
        return;
    }
    light_lens = lens_sample();
    for (var unused = light_subpath_draw_budget() - walk_light_subpath(); unused > 0u; unused--) {
        _ = sample_1d();
    }
}

// The light subpath: a light point and direction (sample_emission), then BSDF sampling. Its
// connectible vertices splat through the camera at once and are kept for the camera subpath's
// connections where a camera vertex can still follow within max_depth. Returns how many numbers
// it drew.
fn walk_light_subpath() -> u32 {
    let u_select = sample_2d();
    let u_position = sample_2d();
    let emitted = sample_emission(u_select, u_position, sample_2d());
    let density = emitted.pdf_position * emitted.pdf_direction;
    let cos_light = dot(emitted.normal, emitted.direction);
    var draws = 3u;
    if !(density > 0.0) || !(cos_light > 0.0) || all(emitted.radiance == vec3<f32>(0.0)) {
        return draws;
    }
    var throughput = emitted.radiance * (cos_light / density);
    var attenuation = vec3<f32>(1.0);
    var sums = emission_mis_sums(emitted, cos_light);
    var ray = Ray(emitted.position, emitted.direction);
    var skip_triangle = NO_TRIANGLE;
    if !emitted.distant && !emitted.delta_position {
        let triangle = scene_triangle(emitted.triangle);
        ray.origin = offset_ray_origin(emitted.position, emitted.normal, emitted.direction, triangle.v0, triangle.v1, triangle.v2);
        skip_triangle = emitted.triangle;
    }
    for (var edges = 1u; ; edges++) {
        count_lanes(LOOP_PATH);
        let hit = closest_hit(ray, FLOAT_MAX, skip_triangle);
        if hit.triangle == NO_TRIANGLE {
            break;
        }
        let v = surface_vertex(ray, hit, scene_triangle(hit.triangle), true);
        sums = mis_sums_at_hit(sums, hit.t, abs(dot(v.geometric, ray.direction)), edges == 1u && emitted.distant);
        if !material_reflects(v.material) {
            break;
        }
        if connectible(v) {
            let splat = connect_to_camera(v, throughput, sums, edges + 1u, light_lens);
            if any(splat.value != vec3<f32>(0.0)) && splat_count < BDPT_LIGHT_VERTICES {
                splats_pending[splat_count] = splat;
                splat_count++;
            }
            if edges + 2u <= frame.max_depth && light_vertex_count < BDPT_LIGHT_VERTICES {
                light_vertices[light_vertex_count] = LightVertex(v, throughput, sums, edges);
                light_vertex_count++;
            }
        }
        // the next vertex would have edges + 1 edges, and light tracing one more
        if edges + 2u > frame.max_depth {
            break;
        }
        let next = sample_scattering(v);
        draws += SCATTERING_DRAWS;
        if next.forward <= 0.0 {
            break;
        }
        throughput *= next.weight;
        attenuation *= next.weight;
        sums = mis_sums_after_scattering(sums, abs(dot(v.geometric, next.direction)), next.forward, next.reverse, next.delta);
        let roulette = play_roulette(edges, attenuation);
        draws += select(0u, 1u, roulette_plays(edges));
        if roulette.ends {
            break;
        }
        throughput /= roulette.survival;
        attenuation /= roulette.survival;
        ray = vertex_ray(v, next.direction);
        skip_triangle = hit.triangle;
    }
    return draws;
}

// The camera subpath from `camera`, with every strategy that ends at one of its vertices: emission
// found (s = 0), next-event estimation (s = 1) and connections to the kept light vertices, whose
// shadow rays are traced once the subpath ends (queue_shadowed). The throughput, roulette
// (judging it without refraction's eta^2) and max_depth as in the path tracer's trace_path.
fn trace_camera_subpath(camera: Ray) -> vec3<f32> {
    var ray = camera;
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    var skip_triangle = NO_TRIANGLE;
    var eta_scale = 1.0;
    var sums = camera_mis_sums(camera_ray_density(camera));
    for (var depth = 1u; ; depth++) {
        // this vertex makes t = depth + 1 with the camera
        let t = depth + 1u;
        count_lanes(LOOP_PATH);
        let hit = closest_hit(ray, FLOAT_MAX, skip_triangle);
        if hit.triangle == NO_TRIANGLE {
            if HAS_ESCAPED_LIGHT {
                let weight = select(escaped_emission_weight(sums, ray.direction), 1.0, depth == 1u);
                radiance += throughput * escaped_light(ray.direction, depth == 1u, false, 0.0) * strategy_weight(0u, t, weight);
            }
            break;
        }
        let triangle = scene_triangle(hit.triangle);
        let v = surface_vertex(ray, hit, triangle, false);
        guide_vertex(v.material, v.shading, ray.direction);
        sums = mis_sums_at_hit(sums, hit.t, abs(dot(v.geometric, ray.direction)), depth == 1u && CAMERA_PARALLEL);
        // emission shines from both sides (a single-sided surface's from its front only)
        let surface_emitted = surface_emission(triangle.material, hit.triangle, triangle, v.position, ray.direction);
        if material_emits(v.material) || any(surface_emitted > vec3<f32>(0.0)) {
            let emitted = material_emitted(v.material) + surface_emitted;
            let weight = select(triangle_emission_weight(sums, hit.triangle, triangle, ray.direction), 1.0, depth == 1u);
            radiance += throughput * emitted * strategy_weight(0u, t, weight);
        }
        if !material_reflects(v.material) || depth >= frame.max_depth {
            break;
        }
        if connectible(v) && frame.light_count != 0u {
            // next-event estimation's and one per light vertex within max_depth - 1 - depth edges
            radiance += unblocked_sum_unless_room(frame.max_depth - depth);
            queue_shadowed(next_event(v, sums, t), throughput);
            for (var i = 0u; i < light_vertex_count; i++) {
                let y = light_vertices[i];
                if y.edges + 1u + depth <= frame.max_depth {
                    queue_shadowed(connect_vertices(v, sums, t, y), throughput);
                }
            }
        }
        let next = sample_scattering(v);
        if next.forward <= 0.0 {
            break;
        }
        throughput *= next.weight;
        eta_scale /= next.eta * next.eta;
        sums = mis_sums_after_scattering(sums, abs(dot(v.geometric, next.direction)), next.forward, next.reverse, next.delta);
        let roulette = play_roulette(depth, throughput * eta_scale);
        if roulette.ends {
            break;
        }
        throughput /= roulette.survival;
        ray = vertex_ray(v, next.direction);
        skip_triangle = hit.triangle;
    }
    return radiance + unblocked_sum();
}

fn render_pixel(xy: vec2<u32>) {
    if xy.x >= frame.width || xy.y >= frame.height {
        return;
    }
    let pixel = xy.y * frame.width + xy.x;
    sampler_begin(pixel);
    let jitter = sample_2d();
    let lens = lens_sample();
    let camera = camera_ray(xy, jitter, lens);
    if BDPT_CHECK_WEIGHT_SUMS {
        accumulation[pixel] = accumulate_sample(accumulation[pixel], check_weight_sums(camera, lens));
        sampler_end(pixel);
        return;
    }
    trace_light_subpath();
    let radiance = trace_camera_subpath(camera);
    if loop_budget_spent(frame.width) {
        accumulation[pixel] = drop_cut_short_sample(accumulation[pixel]);
    } else {
        accumulation[pixel] = accumulate_sample(accumulation[pixel], radiance);
        accumulate_guides(pixel, radiance);
        for (var i = 0u; i < splat_count; i++) {
            splat(splats_pending[i].pixel, splats_pending[i].value);
        }
    }
    sampler_end(pixel);
}

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    count_lanes(LOOP_INVOCATION);
    render_pixel(id.xy);
}
