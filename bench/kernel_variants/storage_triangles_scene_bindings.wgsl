// Experiment baseline: scene_bindings.wgsl as it was before the triangles moved to texels (a storage buffer).
//! include "generated/structs.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> triangles: array<Triangle>;
@group(0) @binding(3) var<storage, read> materials: array<Material>;

fn scene_triangle(index: u32) -> Triangle {
    return triangles[index];
}
