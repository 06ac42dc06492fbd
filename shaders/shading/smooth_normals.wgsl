// Smooth shading from per-vertex normals (gpu/shading_normals.py): the normal interpolated across
// the triangle shades (the BSDF's frame), while the geometric normal keeps deciding which side is
// which and where rays start (ray offsets), so interpolated normals cannot make light leak.
//
// Two guards keep shading and geometry from contradicting each other:
// - pbrt's: a direction counts only where the geometric normal sees the same reflection or
//   transmission as the shading normal (wi and wo on the same side of both, or on opposite sides of
//   both); elsewhere the sample is dropped, which would otherwise let light through a surface or
//   reflect it from behind. A viewer below the shading horizon but above the geometric one (at
//   silhouettes) shades with the geometric normal at that point, so it is never black.
// - the shadow terminator: on a coarse mesh a light above the shading horizon can be below the
//   facet, whose own geometry then shadows it in hard facet-shaped steps. We take Chiang, Li and
//   Burley 2019 ("Taming the Shadow Terminator"): every light and BSDF direction is weighted by
//   their shadowing term G' = -G^3 + G^2 + G of G = min(1, cos_geometric / (cos_shading * dot(ns,
//   ng))), which fades light to zero at the geometric horizon, smoothly. Chosen over Hanika 2021's
//   moved ray origin because it needs only the two normals at the hit (no corner positions), never
//   brightens (the weight is at most 1, so throughputs cannot grow) and cannot move an origin
//   through nearby geometry; its cost is a slight darkening near the terminator.

//! include "geometry/barycentric.wgsl"
//! include "shading/shading_weight.wgsl"

// The corner normals interpolated at `p` (barycentric), turned to the geometric side, unit length;
// the geometric normal for flat triangles (zero corner normals), degenerate interpolations (opposite
// corner normals cancelling: no NaN) and views from between the two horizons (unless the override
// SILHOUETTE_GEOMETRIC_NORMAL is off: generated/shading_normals.wgsl declares it).
fn shading_normal(triangle_index: u32, triangle: Triangle, p: vec3<f32>, geometric: vec3<f32>, towards_viewer: vec3<f32>) -> vec3<f32> {
    let corners = corner_attributes[triangle_index];
    if all(corners.normal0 == vec3<f32>(0.0)) {
        return geometric;
    }
    let b = triangle_barycentric(triangle, p);
    var n = (1.0 - b.x - b.y) * corners.normal0 + b.x * corners.normal1 + b.y * corners.normal2;
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
