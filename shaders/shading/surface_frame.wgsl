// surface_frame: the BSDF's frame at a hit of a scene with anisotropic materials, its first axis
// along the surface tangent (textures_hook; other scenes take shading_frame(shading)).
//
// The tangent is the mesh's, as normal maps take it (corner_tangents: a file's TANGENT or
// MikkTSpace's from the texture coordinates), interpolated and made perpendicular to the shading
// normal (Gram-Schmidt, as Mitsuba's shading frame is made from dP/du). Where a mesh has no texture
// coordinates (a zero tangent) it is Mitsuba's fallback: the first axis of coordinate_system (Duff
// et al.'s frame, our shading_frame) of the triangle's normal. The material's anisotropy_rotation
// turns it towards glTF's bitangent, cross(normal, tangent) x w.
//! include "sampling/warps.wgsl"
//! include "generated/instancing.wgsl"

// Below this a tangent has no reliable direction left beside the shading normal.
const SURFACE_TANGENT_MIN_LENGTH: f32 = 1e-6;

fn surface_frame(shading: vec3<f32>, material_index: u32, triangle_index: u32, triangle: Triangle, p: vec3<f32>, geometric: vec3<f32>) -> ShadingFrame {
    let v = corner_vertices(mesh_triangle(triangle_index));
    let b = triangle_barycentric(triangle, p);
    let corner = (1.0 - b.x - b.y) * vertex_tangents[v.x].tangent + b.x * vertex_tangents[v.y].tangent + b.y * vertex_tangents[v.z].tangent;
    let tangent = world_tangent(triangle_index, corner.xyz);
    var along = tangent - shading * dot(shading, tangent);
    // NaN too
    if !(length(along) > SURFACE_TANGENT_MIN_LENGTH) {
        let fallback = shading_frame(geometric).tangent;
        along = fallback - shading * dot(shading, fallback);
    }
    let t = normalize(along);
    let bitangent = cross(shading, t) * select(1.0, -1.0, corner.w < 0.0);
    let angle = material_textures[material_index].anisotropy_rotation;
    let turned = cos(angle) * t + sin(angle) * bitangent;
    return ShadingFrame(turned, cross(shading, turned), shading);
}
