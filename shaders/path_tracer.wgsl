// The path tracing megakernel: one sample per pixel per dispatch, added to the accumulation buffer.
//! include "acceleration.wgsl"
//! include "camera.wgsl"
//! include "rng.wgsl"
//! include "bsdf.wgsl"
//! include "accumulate.wgsl"

@group(0) @binding(4) var<storage, read_write> rng_states: array<vec4<u32>>;
@group(0) @binding(5) var<storage, read_write> accumulation: array<AccumulatedPixel>;

fn triangle_normal(triangle: Triangle) -> vec3<f32> {
    return normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
}

// One path from the camera: emission at every vertex, BSDF sampling between them, Russian
// roulette (unbiased: survivors are divided by their survival probability) from
// RUSSIAN_ROULETTE_DEPTH on. max_depth counts path vertices the way Mitsuba does: 1 shows only
// emitters seen directly, 2 adds direct lighting, and so on.
fn trace_path(camera: Ray) -> vec3<f32> {
    var ray = camera;
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    var skip_triangle = NO_TRIANGLE;
    for (var depth = 1u; ; depth++) {
        let hit = closest_hit(ray, FLOAT_MAX, skip_triangle);
        if hit.triangle == NO_TRIANGLE {
            break;
        }
        let triangle = triangles[hit.triangle];
        let material = materials[triangle.material];
        if material.kind == MATERIAL_EMITTER {
            // emitters shine from both sides and reflect nothing
            radiance += throughput * material.color;
            break;
        }
        if depth >= frame.max_depth {
            break;
        }
        let normal = triangle_normal(triangle);
        let local = shading_frame(normal);
        let wi = to_local(local, -ray.direction);
        let u = rng_next_2d();
        let sample = bsdf_sample(material, wi, u, rng_next_f32());
        if sample.pdf <= 0.0 {
            break;
        }
        throughput *= sample.weight;
        if depth >= RUSSIAN_ROULETTE_DEPTH {
            let survival = min(max_component(throughput), RUSSIAN_ROULETTE_MAX_SURVIVAL);
            if rng_next_f32() >= survival {
                break;
            }
            throughput /= survival;
        }
        let direction = to_world(local, sample.direction);
        let p = ray.origin + hit.t * ray.direction;
        ray = Ray(offset_ray_origin(p, normal, direction, triangle.v0, triangle.v1, triangle.v2), direction);
        skip_triangle = hit.triangle;
    }
    return radiance;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let pixel = id.y * frame.width + id.x;
    rng_state = rng_states[pixel];
    let radiance = trace_path(camera_ray(id.xy, rng_next_2d()));
    accumulation[pixel] = accumulate_sample(accumulation[pixel], radiance);
    rng_states[pixel] = rng_state;
}
