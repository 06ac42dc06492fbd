// What the variance-guided filter's passes share: the G-buffer's edge stops.
//! include "generated/svgf.wgsl"
//! include "view/tone_curves.wgsl"
//! include "temporal/gbuffer_neighbours.wgsl"

// How much a tap that hit `there` says about the pixel that hit `here`, where the depth of
// `here`'s surface would change by `expected` between them: nothing across the sky's edge, less
// across depth steps beyond the slope and across normals (Schied et al.'s depth and normal stops;
// SVGF_DEPTH_FLOOR of the distance keeps a surface facing the camera from stopping at rounding).
fn geometry_weight(here: GBufferPixel, there: GBufferPixel, expected: f32) -> f32 {
    if (here.surface == 0u) != (there.surface == 0u) {
        return 0.0;
    }
    if here.surface == 0u {
        return 1.0;
    }
    let depth = exp(-abs(here.depth - there.depth) / (SVGF_DEPTH_SIGMA * expected + SVGF_DEPTH_FLOOR * here.depth));
    let normal = pow(max(dot(here.normal, there.normal), 0.0), SVGF_NORMAL_POWER);
    return depth * normal;
}
