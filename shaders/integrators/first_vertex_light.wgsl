// A path's first vertex takes its direct light as every other vertex does (direct_light): the
// path tracers' choice, where the restir integrator resamples (resampled_direct_light.wgsl).

const RESAMPLES_FIRST_VERTEX: bool = false;

fn first_vertex_light(p: vec3<f32>, triangle: Triangle, triangle_index: u32, local: ShadingFrame, geometric: vec3<f32>, towards_viewer: vec3<f32>, material: Material, wi: vec3<f32>) -> vec3<f32> {
    return direct_light(p, triangle, triangle_index, local, geometric, towards_viewer, material, wi);
}
