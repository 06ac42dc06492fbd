// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013).
//! include "geometry/ray.wgsl"
//! include "geometry/difference_of_products.wgsl"
//
// The ray is turned into a shear that maps its direction onto +z; a triangle is hit when the 2D
// edge functions of its sheared corners share a sign. Shared edges are evaluated identically from
// both sides, and each edge function's sign is exact whatever the compiler contracts
// (difference_of_products), so no ray slips between two triangles. Zero-area triangles and
// rays in a triangle's plane give a zero determinant and never hit. No division by a direction
// component other than the largest one, so axis-parallel rays need no special case.

struct ShearedRay {
    origin: vec3<f32>,
    // rows of the shear: p' = (dot(row_x, p - o), dot(row_y, p - o), dot(row_z, p - o))
    row_x: vec3<f32>,
    row_y: vec3<f32>,
    row_z: vec3<f32>,
}

fn axis_vector(axis: u32) -> vec3<f32> {
    return vec3<f32>(f32(axis == 0u), f32(axis == 1u), f32(axis == 2u));
}

fn shear_ray(ray: Ray) -> ShearedRay {
    let a = abs(ray.direction);
    var kz = 2u;
    if a.x >= a.y && a.x >= a.z {
        kz = 0u;
    } else if a.y >= a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    let dz = ray.direction[kz];
    if dz < 0.0 {
        // keep the winding, so the sign of the determinant still tells front from back
        let swap = kx;
        kx = ky;
        ky = swap;
    }
    let ez = axis_vector(kz);
    return ShearedRay(
        ray.origin,
        axis_vector(kx) - (ray.direction[kx] / dz) * ez,
        axis_vector(ky) - (ray.direction[ky] / dz) * ez,
        ez / dz,
    );
}

// Distance along the ray to the triangle, or FLOAT_MAX when it misses or is not nearer than t_max.
fn intersect_triangle(ray: ShearedRay, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, t_max: f32) -> f32 {
    let a = v0 - ray.origin;
    let b = v1 - ray.origin;
    let c = v2 - ray.origin;
    let ax = dot(ray.row_x, a);
    let ay = dot(ray.row_y, a);
    let bx = dot(ray.row_x, b);
    let by = dot(ray.row_y, b);
    let cx = dot(ray.row_x, c);
    let cy = dot(ray.row_y, c);
    let u = difference_of_products(cx, by, cy, bx);
    let v = difference_of_products(ax, cy, ay, cx);
    let w = difference_of_products(bx, ay, by, ax);
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return FLOAT_MAX;
    }
    let det = u + v + w;
    if det == 0.0 {
        return FLOAT_MAX;
    }
    let t = (u * dot(ray.row_z, a) + v * dot(ray.row_z, b) + w * dot(ray.row_z, c)) / det;
    return select(FLOAT_MAX, t, t > 0.0 && t < t_max);
}
