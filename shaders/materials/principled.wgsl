// Principled: Mitsuba 3's `principled` BSDF (Burley's Disney BSDF), less two of its parameters.
//
// Without spec_tint and flatness: a Disney diffuse lobe with
// retro-reflection (weight (1 - metallic)(1 - spec_trans)), a GGX specular reflection whose Fresnel
// mixes the exact dielectric one (eta) and Schlick's about base_color by metallic, and a rough
// dielectric transmission (weight (1 - metallic) spec_trans, tinted sqrt(base_color)). With
// spec_trans 0 the material is two-sided (bsdf_eval and co. mirror wi below the surface: Mitsuba's
// `twosided`); with transmission the side below is the inside (eta inverted), where only the
// dielectric reflects and transmits, weighted by (1 - metallic) spec_trans. eval, pdf and sample
// transcribe Mitsuba's src/bsdfs/principled.cpp and principledhelpers.h for these parameters
// (radiance transport), so that renders match Mitsuba's references. f includes |cos theta_o|.
// From outside, the clearcoat and sheen lobes add to these where the scene uses them (their files,
// or stubs that return nothing: generated/principled_lobes.wgsl). The GGX of both specular lobes is
// principled_ggx_*: isotropic of alpha principled_alpha, or where the scene uses anisotropy
// principled_anisotropic.wgsl's, whose x axis is the surface tangent.
//! include "sampling/warps.wgsl"
//! include "materials/bsdf_sample.wgsl"
//! include "materials/glossy.wgsl"
//! include "materials/glass.wgsl"
//! include "materials/principled_parameters.wgsl"
//! include "generated/principled_lobes.wgsl"

// The lobes' probabilities (Mitsuba's sampling rates: 1, and 0.25 clearcoat for the clearcoat),
// from the side of wi (outside: diffuse, reflection, transmission and clearcoat; inside: the
// dielectric's reflection and transmission) and the dielectric Fresnel reflectance at the
// microfacet; reflection takes what the others leave. Terms of the clearcoat come last in every sum,
// where a scene without it adds a constant 0 that the compiler drops.
struct PrincipledLobes {
    diffuse: f32,
    reflection: f32,
    transmission: f32,
    clearcoat: f32,
}

fn principled_lobes(p: Principled, outside: bool, fresnel: f32) -> PrincipledLobes {
    let bsdf = principled_bsdf_weight(p);
    var lobes = PrincipledLobes(0.0, fresnel, 1.0 - fresnel, 0.0);
    if outside {
        lobes = PrincipledLobes(
            principled_brdf_weight(p),
            1.0 - bsdf * (1.0 - fresnel),
            bsdf * (1.0 - fresnel),
            principled_clearcoat_rate(p),
        );
    }
    let total = lobes.diffuse + lobes.reflection + lobes.transmission + lobes.clearcoat;
    let diffuse = lobes.diffuse / total;
    let transmission = lobes.transmission / total;
    let clearcoat = lobes.clearcoat / total;
    return PrincipledLobes(diffuse, 1.0 - diffuse - transmission - clearcoat, transmission, clearcoat);
}

// eta of the medium wo enters over that of wi's (Mitsuba's eta_path): eta from outside, 1 / eta from inside.
fn principled_eta_path(p: Principled, wi: vec3<f32>) -> f32 {
    return select(1.0 / p.eta, p.eta, wi.z > 0.0);
}

// The half vector of wi and wo, towards +z: of a reflection, or of a refraction by eta_path.
fn principled_half_vector(p: Principled, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let reflects = wi.z * wo.z > 0.0;
    let h = normalize(wi + wo * select(principled_eta_path(p, wi), 1.0, reflects));
    return select(h, -h, h.z < 0.0);
}

// Mitsuba's mac_mic_compatibility: wi on the side of the microfacet m (turned to wi's side) and wo
// on the same side for a reflection, the other for a refraction.
fn principled_compatible(m: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>, reflects: bool) -> bool {
    let m_wi = select(m, -m, wi.z < 0.0);
    return dot(wi, m_wi) > 0.0 && select(-dot(wo, m_wi), dot(wo, m_wi), reflects) > 0.0;
}

// Disney diffuse with retro-reflection, f cos_o, for wi and wo above the surface.
fn principled_diffuse(p: Principled, wi: vec3<f32>, wo: vec3<f32>, h: vec3<f32>) -> vec3<f32> {
    let f_o = schlick_weight(wo.z);
    let f_i = schlick_weight(wi.z);
    let lambert = (1.0 - 0.5 * f_i) * (1.0 - 0.5 * f_o);
    let cos_d = dot(h, wo);
    let r_r = 2.0 * p.roughness * cos_d * cos_d;
    let retro = r_r * (f_o + f_i + f_o * f_i * (r_r - 1.0));
    return p.base_color * (principled_brdf_weight(p) * wo.z * INV_PI * (lambert + retro));
}

fn principled_eval(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let p = principled_parameters(material);
    let outside = wi.z > 0.0;
    let bsdf = principled_bsdf_weight(p);
    // inside a material that transmits nothing there is nothing to see
    if abs(wi.z) <= COS_MIN || abs(wo.z) <= COS_MIN || (!outside && bsdf <= 0.0) {
        return vec3<f32>(0.0);
    }
    let reflects = wi.z * wo.z > 0.0;
    if !reflects && bsdf <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = principled_half_vector(p, wi, wo);
    let cos_ih = dot(wi, h);
    let dielectric = fresnel_dielectric(cos_ih, p.eta).reflectance;
    let g = principled_ggx_g1(p, wi, h) * principled_ggx_g1(p, wo, h);
    let compatible = principled_compatible(h, wi, wo, reflects);
    if reflects {
        var diffuse = vec3<f32>(0.0);
        var clearcoat = 0.0;
        // outside: dielectric and Schlick mixed by metallic; inside: the transmissive lobe's dielectric
        var fresnel = vec3<f32>(bsdf * dielectric);
        if outside {
            diffuse = principled_diffuse(p, wi, wo, h) + principled_sheen(p, wo, h);
            clearcoat = principled_clearcoat_eval(p, wi, wo, h);
            fresnel = mix(vec3<f32>(dielectric), principled_schlick(p.base_color, cos_ih, p.eta), p.metallic);
        }
        if !compatible {
            return diffuse;
        }
        return fresnel * (principled_ggx_d(p, h) * g / (4.0 * abs(wi.z))) + diffuse + vec3<f32>(clearcoat);
    }
    if !compatible {
        return vec3<f32>(0.0);
    }
    // Mitsuba's rough dielectric transmission in radiance transport (its eta_path^2 and the
    // radiance's 1 / eta_path^2 cancel)
    let eta_path = principled_eta_path(p, wi);
    let denominator = cos_ih + eta_path * dot(wo, h);
    let transmitted = (1.0 - dielectric) * principled_ggx_d(p, h) * g * abs(cos_ih * dot(wo, h) / (wi.z * denominator * denominator));
    return sqrt(p.base_color) * (bsdf * transmitted);
}

fn principled_pdf(material: Material, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = principled_parameters(material);
    let outside = wi.z > 0.0;
    let reflects = wi.z * wo.z > 0.0;
    let bsdf = principled_bsdf_weight(p);
    if abs(wi.z) <= COS_MIN || abs(wo.z) <= COS_MIN || (!outside && bsdf <= 0.0) || (!reflects && bsdf <= 0.0) {
        return 0.0;
    }
    let h = principled_half_vector(p, wi, wo);
    let lobes = principled_lobes(p, outside, fresnel_dielectric(dot(wi, h), p.eta).reflectance);
    let compatible = principled_compatible(h, wi, wo, reflects);
    // visible normals of wi turned outwards (G1 D |wi.h| / |wi.z|) times the Jacobian dh/dwo
    let wi_up = select(wi, -wi, wi.z < 0.0);
    if reflects {
        let specular = select(0.0, principled_ggx_reflection_pdf(p, wi_up, h), compatible);
        let clearcoat = select(0.0, principled_clearcoat_pdf(p, wo, h), compatible);
        return lobes.reflection * specular + lobes.diffuse * select(0.0, pdf_cosine_hemisphere(wo.z), outside)
            + lobes.clearcoat * clearcoat;
    }
    if !compatible {
        return 0.0;
    }
    let eta_path = principled_eta_path(p, wi);
    let denominator = dot(wi, h) + eta_path * dot(wo, h);
    let jacobian = abs(eta_path * eta_path * dot(wo, h) / (denominator * denominator));
    let visible = principled_ggx_g1(p, wi_up, h) * principled_ggx_d(p, h) * abs(dot(wi_up, h)) / abs(wi.z);
    return lobes.transmission * visible * jacobian;
}

// One lobe drawn by u_lobe, weighted by the whole BSDF over the mixture's density, as Mitsuba does.
fn principled_sample(material: Material, wi: vec3<f32>, u: vec2<f32>, u_lobe: f32) -> BsdfSample {
    let p = principled_parameters(material);
    let outside = wi.z > 0.0;
    if abs(wi.z) <= COS_MIN || (!outside && principled_bsdf_weight(p) <= 0.0) {
        return no_bsdf_sample();
    }
    let wi_up = select(wi, -wi, wi.z < 0.0);
    let m = principled_ggx_visible_normal(p, wi_up, u);
    let fresnel = fresnel_dielectric(dot(wi, m), p.eta);
    let lobes = principled_lobes(p, outside, fresnel.reflectance);
    var wo: vec3<f32>;
    var eta = 1.0;
    var refracts = false;
    if u_lobe < lobes.diffuse {
        wo = sample_cosine_hemisphere(u);
    } else if u_lobe < lobes.diffuse + lobes.transmission {
        // refraction of wi about m (Mitsuba's refract with the Fresnel's cos_theta_t and eta_ti)
        wo = fresnel.eta_ti * -wi + (fresnel.eta_ti * dot(wi, m) + fresnel.cos_theta_t) * m;
        eta = fresnel.eta_ti;
        refracts = true;
    } else if lobes.clearcoat > 0.0 && u_lobe >= 1.0 - lobes.clearcoat {
        // the clearcoat's share at the top, so that the others' draws are the same without it
        wo = reflect(-wi, principled_clearcoat_normal(p, u));
    } else {
        wo = reflect(-wi, m);
    }
    let pdf = principled_pdf(material, wi, wo);
    // a reflection that leaves on the other side (or a refraction on the same) is no sample of its
    // lobe: the pdf there is another lobe's
    if pdf <= 0.0 || (wi.z * wo.z < 0.0) != refracts {
        return no_bsdf_sample();
    }
    return BsdfSample(wo, principled_eval(material, wi, wo) / pdf, pdf, false, eta);
}
