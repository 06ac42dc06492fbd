// The scene's resources (SCENE_GROUP), shared by every kernel that traces rays.
//! include "generated/structs.wgsl"
//! include "generated/texel_loaders.wgsl"
//! include "generated/bindings/scene.wgsl"

// Every read of a triangle goes through here: the triangles are texels (texel_loader), which on
// lavapipe load in a fraction of a storage load's time (bench/README.md).
fn scene_triangle(index: u32) -> Triangle {
    return load_Triangle(triangles, index);
}
