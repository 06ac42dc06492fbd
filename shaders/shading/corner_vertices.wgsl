// corner_vertices: where a triangle's shading attributes are, its corners' indices in the vertex arrays.
// Attributes are stored once per vertex (TRIANGLE_VERTICES, `shared_vertices`); every attribute
// fetch goes through this one function of the triangle's id, so a change in how triangles find
// their vertices (an instanced mesh's offset) is made here alone.

fn corner_vertices(triangle_index: u32) -> vec3<u32> {
    let corners = triangle_vertices[triangle_index];
    return vec3<u32>(corners.v0, corners.v1, corners.v2);
}
