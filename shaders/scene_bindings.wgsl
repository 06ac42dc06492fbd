// The scene's buffers (bind group 0), shared by every kernel that traces rays.
//! include "generated/structs.wgsl"

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> triangles: array<Triangle>;
@group(0) @binding(2) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(3) var<storage, read> materials: array<Material>;
