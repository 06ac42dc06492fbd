// A path's first vertex takes its direct light as every other vertex does (direct_light): the
// path tracers' choice, where the restir integrator resamples (restir/resampled_direct_light.wgsl).
// path_vertex asks RESAMPLES_FIRST_VERTEX before calling first_vertex_light, so this one is never
// called and compiles to nothing.

const RESAMPLES_FIRST_VERTEX: bool = false;

fn first_vertex_light(point: ShadedPoint, pixel: u32) -> VertexLight {
    return VertexLight(direct_light(point), 1.0);
}
