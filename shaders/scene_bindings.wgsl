// The scene's buffers (bind group 0), shared by every kernel that traces rays.
//! include "generated/structs.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> triangles: array<Triangle>;
// Binding 2 holds the acceleration structure's nodes; each traversal file declares it in the form
// it reads (a texture of node texels for the BVH, a storage buffer for the flat list).
@group(0) @binding(3) var<storage, read> materials: array<Material>;
