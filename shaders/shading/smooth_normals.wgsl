// shading_normal: smooth shading from per-vertex normals (shading_normals_hook compiles it in).
//
// The normal interpolated across the triangle shades (the BSDF's frame), while the geometric normal
// keeps deciding which side is which and where rays start (ray offsets), so interpolated normals
// cannot make light leak; shading_weight guards the directions where the two disagree.

//! include "geometry/barycentric.wgsl"
//! include "shading/corner_vertices.wgsl"
//! include "shading/shading_weight.wgsl"
//! include "generated/instancing.wgsl"

fn vertex_normal(vertex: u32) -> vec3<f32> {
    let n = vertex_normals[vertex];
    return vec3<f32>(n.x, n.y, n.z);
}

// The corner normals interpolated at `p` (barycentric), turned to the geometric side, unit length;
// the geometric normal for flat triangles (zero corner normals), degenerate interpolations (opposite
// corner normals cancelling: no NaN) and views from between the two horizons (unless the override
// SILHOUETTE_GEOMETRIC_NORMAL is off: shading_normals_hook declares it). A viewer below the shading
// horizon but above the geometric one (at silhouettes) thus shades with the geometric normal at that
// point, so it is never black.
fn shading_normal(triangle_index: u32, triangle: Triangle, p: vec3<f32>, geometric: vec3<f32>, towards_viewer: vec3<f32>) -> vec3<f32> {
    let v = corner_vertices(mesh_triangle(triangle_index));
    let normal0 = vertex_normal(v.x);
    if all(normal0 == vec3<f32>(0.0)) {
        return geometric;
    }
    let b = triangle_barycentric(triangle, p);
    var n = world_normal(triangle_index, (1.0 - b.x - b.y) * normal0 + b.x * vertex_normal(v.y) + b.y * vertex_normal(v.z));
    let n_length = length(n);
    // NaN too: a zero-area triangle's determinant is 0
    if !(n_length > SHADING_NORMAL_MIN_LENGTH) {
        return geometric;
    }
    n = n / n_length;
    // normals given against the winding shade the side the geometry says is out
    n = select(n, -n, dot(n, geometric) < 0.0);
    if SILHOUETTE_GEOMETRIC_NORMAL && dot(n, towards_viewer) * dot(geometric, towards_viewer) <= 0.0 {
        return geometric;
    }
    return n;
}
