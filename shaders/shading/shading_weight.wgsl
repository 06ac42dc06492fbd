// shading_weight: what a direction keeps of a BSDF evaluated in the frame of a shading normal that
// differs from the geometric one (interpolated, shading_normals.wgsl, or normal-mapped,
// normal_map.wgsl); the reasons are in shading_normals.wgsl's opening comment.

// What a direction `direction` leaving the vertex seen from `towards_viewer` keeps of the BSDF
// evaluated in the frame of `shading`: 0 where the geometric normal disagrees on reflection against
// transmission, else Chiang et al.'s shadowing term (1 where shading and geometric normals agree,
// and with the override SHADOW_TERMINATOR_TERM off: generated/shading_normals.wgsl declares it).
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
