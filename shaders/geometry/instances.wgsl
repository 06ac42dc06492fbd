// Instances: hit words (slot << INSTANCE_TRIANGLE_BITS | triangle) and what takes a mesh's triangle, normals and tangents to the world.
//! include "generated/structs.wgsl"
//! include "geometry/ray.wgsl"
//! include "generated/bindings/scene.wgsl"
//
// Slot 0 is the scene's own shapes, already in the world; slot s > 0 the instance of record s - 1.
// Directions are not renormalised on the way into object space, so a ray's t is the same there.

// The triangle's index in `triangles` and every per-triangle array.
fn mesh_triangle(word: u32) -> u32 {
    return word & INSTANCE_TRIANGLE_MASK;
}

fn instance_slot(word: u32) -> u32 {
    return word >> INSTANCE_TRIANGLE_BITS;
}

fn object_to_world_point(instance: Instance, p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(instance.object_to_world0.xyz, p) + instance.object_to_world0.w,
        dot(instance.object_to_world1.xyz, p) + instance.object_to_world1.w,
        dot(instance.object_to_world2.xyz, p) + instance.object_to_world2.w,
    );
}

// `ray` in the object space of `instance`: same t along both.
fn object_ray(instance: Instance, ray: Ray) -> Ray {
    let origin = vec3<f32>(
        dot(instance.world_to_object0.xyz, ray.origin) + instance.world_to_object0.w,
        dot(instance.world_to_object1.xyz, ray.origin) + instance.world_to_object1.w,
        dot(instance.world_to_object2.xyz, ray.origin) + instance.world_to_object2.w,
    );
    let direction = vec3<f32>(
        dot(instance.world_to_object0.xyz, ray.direction),
        dot(instance.world_to_object1.xyz, ray.direction),
        dot(instance.world_to_object2.xyz, ray.direction),
    );
    return Ray(origin, direction);
}

// The hit word's triangle in world coordinates (`triangle` as stored: object space for an instance).
fn world_triangle(word: u32, triangle: Triangle) -> Triangle {
    let slot = instance_slot(word);
    if slot == 0u {
        return triangle;
    }
    let instance = instances[slot - 1u];
    return Triangle(
        object_to_world_point(instance, triangle.v0),
        triangle.material,
        object_to_world_point(instance, triangle.v1),
        object_to_world_point(instance, triangle.v2),
    );
}

// An object-space normal in the world: the inverse transpose of the linear part (the rows of
// world_to_object weighted by the normal's components), not renormalised.
fn world_normal(word: u32, normal: vec3<f32>) -> vec3<f32> {
    let slot = instance_slot(word);
    if slot == 0u {
        return normal;
    }
    let instance = instances[slot - 1u];
    return normal.x * instance.world_to_object0.xyz + normal.y * instance.world_to_object1.xyz + normal.z * instance.world_to_object2.xyz;
}

// An object-space direction along the surface (a tangent) in the world: the linear part.
fn world_tangent(word: u32, tangent: vec3<f32>) -> vec3<f32> {
    let slot = instance_slot(word);
    if slot == 0u {
        return tangent;
    }
    let instance = instances[slot - 1u];
    return vec3<f32>(dot(instance.object_to_world0.xyz, tangent), dot(instance.object_to_world1.xyz, tangent), dot(instance.object_to_world2.xyz, tangent));
}
