// Vertex colours: vertex_color, interpolated at a hit, and what they do to the material there.
//! include "generated/materials.wgsl"
//! include "geometry/barycentric.wgsl"
//! include "shading/corner_vertices.wgsl"
//! include "generated/instancing.wgsl"

// The linear RGBA vertex colour at `p` on triangle `triangle_index`, interpolated from its corners
// (white for a triangle of a shape without colours). Zero-area triangles, whose barycentric
// weights would be NaN, never reach the GPU (Scene.arrays leaves them out).
fn vertex_color(triangle_index: u32, triangle: Triangle, p: vec3<f32>) -> vec4<f32> {
    let v = corner_vertices(mesh_triangle(triangle_index));
    let b = triangle_barycentric(triangle, p);
    return (1.0 - b.x - b.y) * vertex_colors[v.x].color + b.x * vertex_colors[v.y].color + b.y * vertex_colors[v.z].color;
}

// The material with its colour (albedo, base colour, tint: Material.color) multiplied by the vertex
// colour's RGB. An emitter's colour is its radiance, which the light table has already weighed
// without the vertices (glTF's COLOR_0 multiplies the base colour, never the emission), so it is
// left alone.
fn vertex_colored(material: Material, triangle_index: u32, triangle: Triangle, p: vec3<f32>) -> Material {
    if material_emits(material) {
        return material;
    }
    var colored = material;
    colored.color *= vertex_color(triangle_index, triangle, p).rgb;
    return colored;
}

// The vertex colour's alpha at `p`, which multiplies the material's alpha (surface_blocks).
fn vertex_alpha(triangle_index: u32, triangle: Triangle, p: vec3<f32>) -> f32 {
    return vertex_color(triangle_index, triangle, p).a;
}
