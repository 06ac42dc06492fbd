// The scene's buffers (bind group 0), shared by every kernel that traces rays.
//! include "generated/structs.wgsl"
//! include "generated/texel_loaders.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
// The triangles as texels (gpu/texels.py), like the BVH's nodes: on lavapipe a texture load costs a
// fraction of a storage load (bench/README.md, 2026-11-23).
@group(0) @binding(1) var triangle_texels: texture_2d<u32>;
// Binding 2 holds the acceleration structure's nodes; each traversal file declares it in the form
// it reads (a texture of node texels for the BVH, a storage buffer for the flat list).
@group(0) @binding(3) var<storage, read> materials: array<Material>;

// Every read of a triangle goes through here, so the triangles' binding is declared in one place.
fn scene_triangle(index: u32) -> Triangle {
    return load_Triangle(triangle_texels, index);
}
