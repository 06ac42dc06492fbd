// mapped_normal: the shading normal at a hit bent by its material's normal texture (textures_hook).
// glTF's normalTexture x normal_scale, through the vertex tangents interpolated like the normals.
//! include "shading/normal_map.wgsl"
//! include "generated/instancing.wgsl"

fn mapped_normal(shading: vec3<f32>, material: Material, material_index: u32, triangle_index: u32, triangle: Triangle, p: vec3<f32>, geometric: vec3<f32>, towards_viewer: vec3<f32>) -> vec3<f32> {
    let texture = material_textures[material_index].normal;
    if texture == NO_TEXTURE {
        return shading;
    }
    let texel = texture_sample(texture, surface_uv(triangle_index, triangle, p)).rgb;
    let v = corner_vertices(mesh_triangle(triangle_index));
    let b = triangle_barycentric(triangle, p);
    let tangent = (1.0 - b.x - b.y) * vertex_tangents[v.x].tangent + b.x * vertex_tangents[v.y].tangent + b.y * vertex_tangents[v.z].tangent;
    return normal_mapped(shading, vec4<f32>(world_tangent(triangle_index, tangent.xyz), tangent.w), texel, material_textures[material_index].normal_scale, geometric, towards_viewer);
}
