// The path tracing megakernel: each pixel's samples of a dispatch, added to the accumulation buffer.
//! include "generated/acceleration.wgsl"
// camera_ray: the scene's camera kind (camera_hook)
//! include "generated/camera.wgsl"
//! include "camera/lens_sample.wgsl"
//! include "sampling/sampler.wgsl"
//! include "materials/bsdf.wgsl"
//! include "lights/direct_light_sampler.wgsl"
//! include "sampling/mis.wgsl"
//! include "integrators/accumulate.wgsl"
//! include "integrators/loop_budget.wgsl"
// guide_vertex and accumulate_guides: empty unless the denoiser's guides are compiled in, and
// write_gbuffer unless the G-buffer is (path_guides_hook)
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
// segment_transmittance: 1 unless the scene has an absorbing material (absorption_hook)
//! include "generated/absorption.wgsl"
// samples_this_dispatch: 1, or this dispatch's count where paths regenerate (regeneration_hook)
//! include "generated/regeneration.wgsl"
// first_vertex_light and RESAMPLES_FIRST_VERTEX: the direct light of a path's first vertex, where
// it is resampled (the integrator's first_vertex_light file)
//! include "generated/first_vertex_light.wgsl"
//! include "generated/bindings/pixels.wgsl"
//! include "generated/workgroup.wgsl"

// Which estimator of direct light: BSDF sampling alone, light sampling alone (next-event
// estimation), or both combined by multiple importance sampling. One compile per choice.
override INTEGRATOR: u32 = INTEGRATOR_MIS;

// Russian roulette starts at this path depth and never survives with more than this probability,
// so that paths stuck in lossless loops (total internal reflection) still end. Overrides so that
// bench.error_breakdown can measure other policies.
override RUSSIAN_ROULETTE_DEPTH: u32 = 3u;
override RUSSIAN_ROULETTE_MAX_SURVIVAL: f32 = 0.95;

fn triangle_normal(triangle: Triangle) -> vec3<f32> {
    return normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
}

// Vertices where a light sample can land in the BSDF's lobe (the material says: generated
// material_samples_lights); elsewhere (glass, near-mirror glossy) only BSDF sampling finds lights.
fn samples_lights(material: Material) -> bool {
    if INTEGRATOR == INTEGRATOR_BSDF || frame.light_count == 0u {
        return false;
    }
    return material_samples_lights(material);
}

// Under plain path tracing, vertices that still sample the delta lights (point, spot, directional):
// no BSDF sample can hit one, so light sampling is their only strategy, with weight 1, as under
// every integrator. Only scenes with delta lights compile it in (generated HAS_DELTA_LIGHTS).
fn samples_delta_lights_only(material: Material) -> bool {
    return HAS_DELTA_LIGHTS && INTEGRATOR == INTEGRATOR_BSDF && frame.light_count != 0u && material_samples_lights(material);
}

// Whether anything blocks the way from `origin` to the sampled light: up to the light point, or
// to infinity for distant lights.
fn light_occluded(origin: vec3<f32>, light: LightSample, skip_triangle: u32) -> bool {
    if light.distant {
        return occluded(Ray(origin, light.direction), FLOAT_MAX, skip_triangle);
    }
    // Aim from the moved origin: moved towards a light plane that faces the surface (a lamp just
    // below a ceiling), a ray of the unmoved length would reach the light's plane at grazing angles
    // and count the light as its own occluder.
    let shadow = light.position - origin;
    let shadow_distance = length(shadow);
    return occluded(Ray(origin, shadow / shadow_distance), shadow_distance * SHADOW_RAY_SHORTENING, skip_triangle);
}

// A surface point where a path's vertex estimates light: the hit triangle (number
// `triangle_index`) and its normal `geometric`, the material there (textures and vertex colours
// resolved), the shading frame `local` (normal maps applied) and the direction back along the
// ray, in world space (`towards_viewer`) and in the frame (`wi`).
struct ShadedPoint {
    p: vec3<f32>,
    triangle: Triangle,
    triangle_index: u32,
    geometric: vec3<f32>,
    towards_viewer: vec3<f32>,
    material: Material,
    local: ShadingFrame,
    wi: vec3<f32>,
}

// The point `p` of triangle `triangle_index`, seen from along `towards_viewer`.
fn shaded_point(triangle_index: u32, p: vec3<f32>, towards_viewer: vec3<f32>) -> ShadedPoint {
    let triangle = scene_triangle(triangle_index);
    let normal = triangle_normal(triangle);
    let material = vertex_colored(resolve_material(materials[triangle.material], triangle.material, triangle_index, triangle, p), triangle_index, triangle, p);
    let interpolated = shading_normal(triangle_index, triangle, p, normal, towards_viewer);
    let shading = mapped_normal(interpolated, material, triangle.material, triangle_index, triangle, p, normal, towards_viewer);
    let local = surface_frame(shading, triangle.material, triangle_index, triangle, p, normal);
    return ShadedPoint(p, triangle, triangle_index, normal, towards_viewer, material, local, to_local(local, towards_viewer));
}

// What one light sample would add at `point` if nothing blocked it: the light's radiance times
// the BSDF (cosine included, with what shading_weight keeps of it), not yet divided by the sample's
// density; and the unit direction towards the light.
struct UnshadowedLight {
    value: vec3<f32>,
    direction: vec3<f32>,
}

fn unshadowed_light(point: ShadedPoint, light: LightSample) -> UnshadowedLight {
    var direction = light.direction;
    if !light.distant {
        let to_light = light.position - point.p;
        direction = to_light / sqrt(dot(to_light, to_light));
    }
    let cos_light = abs(dot(light.normal, direction));
    // NaN too: a point light at the receiving point has no direction
    if !(cos_light > COS_MIN) {
        return UnshadowedLight(vec3<f32>(0.0), direction);
    }
    let f = bsdf_eval(point.material, point.wi, to_local(point.local, direction)) * shading_weight(point.local.normal, point.geometric, point.towards_viewer, direction);
    return UnshadowedLight(f * light.radiance, direction);
}

// Whether the shadow ray from `point` reaches the sampled light along `direction`.
fn light_reaches(point: ShadedPoint, light: LightSample, direction: vec3<f32>) -> bool {
    let triangle = point.triangle;
    let origin = offset_ray_origin(point.p, point.geometric, direction, triangle.v0, triangle.v1, triangle.v2);
    return !light_occluded(origin, light, point.triangle_index);
}

// Light reaching `point` from one sampled light point (unshadowed_light's, if the shadow ray
// reaches it), over the sample's density, weighted against BSDF sampling under MIS (delta lights:
// weight 1). Under plain path tracing only delta lights count here.
fn direct_light(point: ShadedPoint) -> vec3<f32> {
    let light = sample_light(point.p, sample_2d(), sample_2d());
    // An environment sample's density is evaluated again from its direction, which f32 rounding
    // can put in a neighbouring cell of density 0 (and radiance 0): no light, not 0 / 0.
    if !(light.pdf > 0.0) {
        return vec3<f32>(0.0);
    }
    if INTEGRATOR == INTEGRATOR_BSDF && !light.delta {
        return vec3<f32>(0.0);
    }
    let unshadowed = unshadowed_light(point, light);
    if all(unshadowed.value == vec3<f32>(0.0)) || !light_reaches(point, light, unshadowed.direction) {
        return vec3<f32>(0.0);
    }
    var weight = 1.0;
    if INTEGRATOR == INTEGRATOR_MIS && !light.delta {
        weight = power_heuristic(light.pdf, bsdf_pdf(point.material, point.wi, to_local(point.local, unshadowed.direction)));
    }
    return unshadowed.value * (weight / light.pdf);
}

// The direct light of a path's first vertex (first_vertex_light), and how many light samples it
// counts as when light found by the vertex's BSDF sample is weighed against it by MIS.
struct VertexLight {
    radiance: vec3<f32>,
    light_samples: f32,
}

// Weight of emission found by following the path: in full where the previous vertex could not
// sample lights (the camera, glass, near-mirrors), not at all under pure NEE (light sampling
// counted it), and by the power heuristic under MIS. `previous_position` is the point the light
// sampler would have sampled from (unmoved by the ray offset, as in direct_light).
fn emission_weight(previous_sampled_lights: bool, previous_bsdf_pdf: f32, previous_position: vec3<f32>, triangle_index: u32, triangle: Triangle, distance: f32, cos_light: f32) -> f32 {
    if !previous_sampled_lights {
        return 1.0;
    }
    if INTEGRATOR == INTEGRATOR_NEE {
        return 0.0;
    }
    return power_heuristic(previous_bsdf_pdf, pdf_light(previous_position, triangle_index, triangle, distance * distance, cos_light));
}

// emission_weight's rule for light found by a ray leaving the scene (the environment, the sun),
// whose light sampler density `light_pdf` for that direction is known (generated escaped_light).
fn escaped_weight(previous_sampled_lights: bool, previous_bsdf_pdf: f32, light_pdf: f32) -> f32 {
    if !previous_sampled_lights {
        return 1.0;
    }
    if INTEGRATOR == INTEGRATOR_NEE {
        return 0.0;
    }
    return power_heuristic(previous_bsdf_pdf, light_pdf);
}

// A path from the camera, between bounces: where its next ray goes and what it carries.
struct PathState {
    ray: Ray,
    radiance: vec3<f32>,
    throughput: vec3<f32>,
    skip_triangle: u32,
    previous_sampled_lights: bool,
    previous_bsdf_pdf: f32,
    previous_position: vec3<f32>,
    eta_scale: f32,
    depth: u32,
    // the index of the pixel it is a sample of
    pixel: u32,
}

fn path_start(camera: Ray, pixel: u32) -> PathState {
    return PathState(camera, vec3<f32>(0.0), vec3<f32>(1.0), NO_TRIANGLE, false, 0.0, vec3<f32>(0.0), 1.0, 1u, pixel);
}

// One vertex of a path from the camera: emission at every vertex, direct light by the chosen
// integrator, BSDF sampling towards the next vertex, Russian roulette (unbiased: survivors are
// divided by their survival probability) from RUSSIAN_ROULETTE_DEPTH on. Returns whether the path
// goes on. Roulette judges the throughput without the eta^2 radiance scaling of refraction (as pbrt
// and Mitsuba do): inside glass that scaling would make paths die more often and survivors carry
// heavier weights, only to undo itself on the way out. max_depth counts path vertices the way
// Mitsuba does: 1 shows only emitters seen directly, 2 adds direct lighting, and so on.
fn path_vertex(path: ptr<function, PathState>) -> bool {
    let ray = (*path).ray;
    let depth = (*path).depth;
    let hit = closest_hit(ray, FLOAT_MAX, (*path).skip_triangle);
    if hit.triangle == NO_TRIANGLE {
        if HAS_ESCAPED_LIGHT {
            (*path).radiance += (*path).throughput * escaped_light(ray.direction, depth == 1u, (*path).previous_sampled_lights, (*path).previous_bsdf_pdf);
        }
        return false;
    }
    let p = ray.origin + hit.t * ray.direction;
    let point = shaded_point(hit.triangle, p, -ray.direction);
    let triangle = point.triangle;
    let normal = point.geometric;
    let material = point.material;
    let shading = point.local.normal;
    guide_vertex(material, shading, ray.direction);
    (*path).throughput *= segment_transmittance(material, normal, ray.direction, hit.t);
    // emission shines from both sides (a single-sided surface's from its front only)
    let surface_emitted = surface_emission(triangle.material, hit.triangle, triangle, p, ray.direction);
    if material_emits(material) || any(surface_emitted > vec3<f32>(0.0)) {
        let emitted = material_emitted(material) + surface_emitted;
        let cos_light = abs(dot(normal, ray.direction));
        let weight = emission_weight((*path).previous_sampled_lights, (*path).previous_bsdf_pdf, (*path).previous_position, hit.triangle, triangle, hit.t, cos_light);
        (*path).radiance += (*path).throughput * emitted * weight;
    }
    if !material_reflects(material) || depth >= frame.max_depth {
        return false;
    }
    let local = point.local;
    let wi = point.wi;
    let towards_viewer = point.towards_viewer;
    (*path).previous_sampled_lights = samples_lights(material);
    (*path).previous_position = p;
    // how many light samples the light this vertex estimated counts as, against its BSDF sample
    var light_samples = 1.0;
    if (*path).previous_sampled_lights || samples_delta_lights_only(material) {
        var light: vec3<f32>;
        // a constant condition: the path tracers that take the first vertex's light as any other's
        // compile one direct_light, not two
        if RESAMPLES_FIRST_VERTEX && depth == 1u {
            let first = first_vertex_light(point, (*path).pixel);
            light = first.radiance;
            light_samples = first.light_samples;
        } else {
            light = direct_light(point);
        }
        (*path).radiance += (*path).throughput * light;
    }
    let u = sample_2d();
    let sample = bsdf_sample(material, wi, u, sample_1d());
    if sample.pdf <= 0.0 {
        return false;
    }
    let direction = to_world(local, sample.direction);
    let kept = shading_weight(shading, normal, towards_viewer, direction);
    if kept <= 0.0 {
        return false;
    }
    // the power heuristic of the BSDF's density against n light samples' is that of density / n against one's
    (*path).previous_bsdf_pdf = sample.pdf / light_samples;
    (*path).throughput *= sample.weight * kept;
    (*path).eta_scale /= sample.eta * sample.eta;
    if depth >= RUSSIAN_ROULETTE_DEPTH {
        let survival = min(max_component((*path).throughput) * (*path).eta_scale, RUSSIAN_ROULETTE_MAX_SURVIVAL);
        if sample_1d() >= survival {
            return false;
        }
        (*path).throughput /= survival;
    }
    (*path).ray = Ray(offset_ray_origin(p, normal, direction, triangle.v0, triangle.v1, triangle.v2), direction);
    (*path).skip_triangle = hit.triangle;
    (*path).depth = depth + 1u;
    return true;
}

// A path's first ray: through the pixel, jittered by the sample's first draw, through the lens
// by its second where the camera has one.
fn camera_path(xy: vec2<u32>) -> PathState {
    let jitter = sample_2d();
    return path_start(camera_ray(xy, jitter, lens_sample()), xy.y * frame.width + xy.x);
}

// The pixel's sum with one finished path added, or counted as cut short and dropped if the
// driver's loop budget may have ended one of its loops (loop_budget_spent).
fn add_sample(sum: AccumulatedPixel, pixel: u32, radiance: vec3<f32>) -> AccumulatedPixel {
    if loop_budget_spent(frame.width) {
        return drop_cut_short_sample(sum);
    }
    accumulate_guides(pixel, radiance);
    return accumulate_sample(sum, radiance);
}

// `samples` samples of the pixel at column xy.x, row xy.y, after any it owes, in one loop over
// path vertices (path regeneration, Novak et al. 2010): a path that ends starts the pixel's next
// sample in the same pass, so that lanes run in lockstep do not wait for their group's longest
// path. Each sample draws, adds and counts as it would alone in its dispatch, in the same order
// (the pixel's sum stays in registers until the last). Under a loop budget (regeneration_hook)
// a sample that finds it spent is left, with those after it, to dispatches of no samples, which
// take one of those a pixel owes each. The viewer's band-of-rows entry point (main_rows) takes one.
fn render_pixel(xy: vec2<u32>, samples: u32) {
    if xy.x >= frame.width || xy.y >= frame.height {
        return;
    }
    let pixel = xy.y * frame.width + xy.x;
    // before the sampler is seeded: the G-buffer's ray draws nothing of the pixel's sequence
    write_gbuffer(xy, pixel);
    let owed = samples_owed(pixel);
    let count = select(owed + samples, min(owed, 1u), samples == 0u);
    if count == 0u {
        return;
    }
    let defers = LOOP_BUDGET && samples != 0u;
    sampler_begin(pixel);
    var sum = accumulation[pixel];
    var path = camera_path(xy);
    var done = 0u;
    loop {
        count_lanes(LOOP_PATH);
        if path_vertex(&path) {
            continue;
        }
        if defers && loop_budget_spent(frame.width) {
            break;
        }
        sum = add_sample(sum, pixel, path.radiance);
        done++;
        if done == count {
            break;
        }
        sampler_next_sample();
        guides_begin();
        path = camera_path(xy);
    }
    // Short of `count`, the budget ran out: the driver ends this loop too, under way or above.
    // Deferring, the sample under way and those after it are owed; otherwise they are cut short.
    let rewound = defers && done < count;
    if done < count && !rewound {
        sum = drop_cut_short_samples(sum, count - done);
        done = count;
    }
    accumulation[pixel] = sum;
    if LOOP_BUDGET {
        owe_samples(pixel, owed, select(owed - done, count - done, defers));
    }
    if rewound {
        sampler_end_rewound(pixel);
    } else {
        sampler_end(pixel);
    }
}

@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    count_lanes(LOOP_INVOCATION);
    render_pixel(id.xy, samples_this_dispatch());
}
