// Ray/box slab test, robust for axis-parallel rays and grazing hits.
//! include "common/constants.wgsl"

// |1/d| at or above this marks a component safe_inverse_direction replaced: half of
// 1 / MIN_DIRECTION_COMPONENT, so that a division rounded either way still counts.
const PARALLEL_INVERSE: f32 = 0.5 / MIN_DIRECTION_COMPONENT;

// 1/d with components too close to zero replaced (sign kept), so slab distances stay finite.
fn safe_inverse_direction(d: vec3<f32>) -> vec3<f32> {
    let sign = select(vec3<f32>(-1.0), vec3<f32>(1.0), d >= vec3<f32>(0.0));
    let safe = select(d, sign * MIN_DIRECTION_COMPONENT, abs(d) < vec3<f32>(MIN_DIRECTION_COMPONENT));
    return 1.0 / safe;
}

// Entry distance into the box if the ray overlaps it within [0, t_max], else FLOAT_MAX.
fn intersect_box(origin: vec3<f32>, inverse_direction: vec3<f32>, bounds_min: vec3<f32>, bounds_max: vec3<f32>, t_max: f32) -> f32 {
    let t0 = (bounds_min - origin) * inverse_direction;
    let t1 = (bounds_max - origin) * inverse_direction;
    let near = min(t0, t1);
    // A ray along a face (a direction component replaced by safe_inverse_direction, origin on that
    // face's plane) would get the exit distance 0 * 1e30 = 0 there and miss the box it touches:
    // such a slab does not bound the ray.
    let along_face = (abs(inverse_direction) >= vec3<f32>(PARALLEL_INVERSE)) & (max(t0, t1) == vec3<f32>(0.0));
    let far = select(max(t0, t1), vec3<f32>(FLOAT_MAX), along_face);
    let t_enter = max(max(near.x, near.y), max(near.z, 0.0));
    let t_exit = min(min(far.x, far.y), min(far.z, t_max)) * BOX_FAR_SCALE;
    return select(FLOAT_MAX, t_enter, t_enter <= t_exit);
}
