// Glossy: GGX microfacet reflection (Fresnel = color), sampled by its visible normals (Heitz 2018).
// Smith's separable shadowing; eval, sample and pdf share the same D and G1.
//! include "sampling/warps.wgsl"
//! include "materials/bsdf_sample.wgsl"

// Glossy lobes narrower than this roughness are treated like mirrors: light sampling would almost
// never land in the lobe, so those vertices skip next-event estimation (Glossy.samples_lights) and
// their BSDF-sampled hits on emitters count in full. The choice does not bias the estimate, only
// its noise; bench.glossy_light_sampling measures it (a glossy sphere under a small light, MIS).
override GLOSSY_LIGHT_SAMPLING_MIN_ROUGHNESS: f32 = 0.005;

fn ggx_alpha(roughness: f32) -> f32 {
    return max(roughness, GGX_ALPHA_MIN);
}

// Normal distribution D(m) of GGX, for m in the upper hemisphere.
fn ggx_d(m: vec3<f32>, alpha: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let s = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
    return 1.0 / (PI * a2 * s * s);
}

// Smith's masking G1(v, m) for GGX; zero where v sees the back of the microfacet.
fn ggx_smith_g1(v: vec3<f32>, m: vec3<f32>, alpha: f32) -> f32 {
    if dot(v, m) * v.z <= 0.0 {
        return 0.0;
    }
    let tan2_alpha2 = alpha * alpha * (v.x * v.x + v.y * v.y) / (v.z * v.z);
    return 2.0 / (1.0 + sqrt(1.0 + tan2_alpha2));
}

// A microfacet normal drawn from D_wi(m) = G1(wi, m) max(0, wi.m) D(m) / wi.z.
fn sample_ggx_visible_normal(wi: vec3<f32>, alpha: f32, u: vec2<f32>) -> vec3<f32> {
    let vh = normalize(vec3<f32>(alpha * wi.x, alpha * wi.y, wi.z));
    let length2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(length2), length2 > 0.0);
    let t2 = cross(vh, t1);
    let r = sqrt(u.x);
    let phi = TWO_PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(0.0, nh.z)));
}

// Density of wo = reflect(-wi, m) for m drawn by sample_ggx_visible_normal: the normal density
// D_wi(m) = G1(wi, m) max(0, wi.m) D(m) / wi.z times the Jacobian 1 / (4 wo.m) of reflection.
// For the half vector m of wi and wo, wi.m = wo.m exactly, so they cancel here: near grazing
// both are ~(wi.z + wo.z) / 2, tiny, and computing them apart from a float32 wi (|wi| = 1 only to
// within a rounding) made the pdf 4% too large at wi.z = 1e-3, alpha = 0.01 (found by the
// chi-square test, test_bsdf_chi_square).
fn pdf_ggx_reflection(wi: vec3<f32>, m: vec3<f32>, alpha: f32) -> f32 {
    return ggx_smith_g1(wi, m, alpha) * ggx_d(m, alpha) / (4.0 * wi.z);
}

fn glossy_eval(color: vec3<f32>, roughness: f32, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= COS_MIN || wo.z <= COS_MIN {
        return vec3<f32>(0.0);
    }
    let alpha = ggx_alpha(roughness);
    let m = normalize(wi + wo);
    // f cos_o = F D G1(wi) G1(wo) / (4 wi.z wo.z) * wo.z
    return color * (ggx_d(m, alpha) * ggx_smith_g1(wi, m, alpha) * ggx_smith_g1(wo, m, alpha) / (4.0 * wi.z));
}

fn glossy_pdf(roughness: f32, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wi.z <= COS_MIN || wo.z <= COS_MIN {
        return 0.0;
    }
    return pdf_ggx_reflection(wi, normalize(wi + wo), ggx_alpha(roughness));
}

fn glossy_sample(color: vec3<f32>, roughness: f32, wi: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    if wi.z <= COS_MIN {
        return no_bsdf_sample();
    }
    let alpha = ggx_alpha(roughness);
    let m = sample_ggx_visible_normal(wi, alpha, u);
    let wo = reflect(-wi, m);
    if wo.z <= COS_MIN {
        return no_bsdf_sample();
    }
    // eval / pdf: D and G1(wi) cancel, leaving F G1(wo)
    return BsdfSample(wo, color * ggx_smith_g1(wo, m, alpha), glossy_pdf(roughness, wi, wo), false, 1.0);
}
