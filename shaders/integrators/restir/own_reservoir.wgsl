// A first vertex's reservoir of its own candidates alone (vertex_reservoir): the restir
// integrator's as shipped, and wherever part of the image is traced (the viewer's bands).

fn vertex_reservoir(point: ShadedPoint, pixel: u32) -> VertexReservoir {
    let fresh = candidate_reservoir(point);
    let count = f32(RESAMPLED_LIGHT_CANDIDATES);
    return VertexReservoir(fresh.kept, contribution_weight(fresh) / count, count);
}
