// Principled's sheen: Mitsuba 3's transcription of Burley's sheen, a grazing-angle lobe for cloth.
//
// f cos_o = sheen (1 - metallic) (1 - cos_d)^5 c cos_o, cos_d between the half vector and wo, c
// blended by sheen_tint from white to base_color over its luminance. Mitsuba adds it in its diffuse
// block, masked by metallic < 1 but not by the diffuse weight (its JIT variants, which render the
// references, enter the block whatever that weight): with spec_trans 1 it shines too. The diffuse
// lobe's samples, where there are any, and the specular ones cover it.
// Compiled only into kernels of scenes that use it (generated/principled_lobes.wgsl).
//! include "materials/principled_parameters.wgsl"

// Mitsuba's luminance weights in its RGB modes (linear sRGB's Y, unrounded: the references' tint)
const SHEEN_LUMINANCE_WEIGHTS: vec3<f32> = vec3<f32>(0.212671, 0.715160, 0.072169);

// f cos_o for wi and wo above the surface, h their half vector
fn principled_sheen(p: Principled, wo: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    if p.sheen <= 0.0 || p.metallic >= 1.0 {
        return vec3<f32>(0.0);
    }
    let luminance = dot(SHEEN_LUMINANCE_WEIGHTS, p.base_color);
    let tint = select(vec3<f32>(1.0), p.base_color / luminance, luminance > 0.0);
    let color = mix(vec3<f32>(1.0), tint, p.sheen_tint);
    return color * (p.sheen * (1.0 - p.metallic) * schlick_weight(abs(dot(h, wo))) * wo.z);
}
