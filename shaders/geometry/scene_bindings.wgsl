// The scene's resources (SCENE_GROUP), shared by every kernel that traces rays.
//! include "generated/structs.wgsl"
//! include "generated/texel_loaders.wgsl"
//! include "generated/bindings/scene.wgsl"
//! include "generated/instancing.wgsl"

// Every read of a triangle goes through here: the triangles are texels (texel_loader), which on
// lavapipe load in a fraction of a storage load's time (bench/README.md). `index` is a hit word: in a
// scene with instances their triangles come out in world coordinates.
fn scene_triangle(index: u32) -> Triangle {
    return world_triangle(index, load_Triangle(triangles, mesh_triangle(index)));
}
