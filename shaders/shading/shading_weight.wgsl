// shading_weight: what a direction keeps of a BSDF evaluated in the frame of a shading normal.
// For normals that differ from the geometric one: interpolated (shading_normal) or mapped (normal_mapped).

// What a direction `direction` leaving the vertex seen from `towards_viewer` keeps of the BSDF
// evaluated in the frame of `shading`, by two guards that keep shading and geometry from
// contradicting each other:
// - pbrt's: 0 where the geometric normal disagrees with the shading normal on reflection against
//   transmission (wi and wo on the same side of both, or on opposite sides of both); such a sample
//   would let light through a surface or reflect it from behind.
// - the shadow terminator: on a coarse mesh a light above the shading horizon can be below the
//   facet, whose own geometry then shadows it in hard facet-shaped steps. Chiang, Li and Burley 2019
//   ("Taming the Shadow Terminator") weigh every light and BSDF direction by their shadowing term
//   G' = -G^3 + G^2 + G of G = min(1, cos_geometric / (cos_shading * dot(ns, ng))), which fades
//   light to zero at the geometric horizon, smoothly. Chosen over Hanika 2021's moved ray origin
//   because it needs only the two normals at the hit (no corner positions), never brightens (the
//   weight is at most 1, so throughputs cannot grow) and cannot move an origin through nearby
//   geometry; its cost is a slight darkening near the terminator. The term is 1 where shading and
//   geometric normals agree, and with the override SHADOW_TERMINATOR_TERM off (shading_normals_hook
//   declares it).
fn shading_weight(shading: vec3<f32>, geometric: vec3<f32>, towards_viewer: vec3<f32>, direction: vec3<f32>) -> f32 {
    let geometric_reflects = dot(geometric, towards_viewer) * dot(geometric, direction) > 0.0;
    let shading_reflects = dot(shading, towards_viewer) * dot(shading, direction) > 0.0;
    if geometric_reflects != shading_reflects {
        return 0.0;
    }
    if !SHADOW_TERMINATOR_TERM {
        return 1.0;
    }
    let cos_shading = abs(dot(shading, direction)) * dot(shading, geometric);
    let g = min(1.0, abs(dot(geometric, direction)) / max(cos_shading, SHADING_NORMAL_MIN_LENGTH));
    return g * (1.0 + g - g * g);
}
