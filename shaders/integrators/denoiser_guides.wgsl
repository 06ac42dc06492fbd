// The denoiser's guides: albedo and shading normal of each path's first non-delta vertex, summed per pixel.
//! include "generated/structs.wgsl"
//! include "integrators/accumulate.wgsl"
//! include "generated/bindings/pixels.wgsl"
//
// Open Image Denoise asks for the features of the first diffuse or glossy surface, following
// perfect specular (delta) paths through mirrors and glass: a path chooses reflection or
// refraction by Fresnel, so the mean over a pixel's samples is the Fresnel blend its documentation
// recommends. A path that escapes or ends before such a vertex adds zero to both sums.
// `material_is_delta` is generated for the scene's kinds (path_guides_hook).

// The path under way (zero-initialized for an invocation's first path, guides_begin for the next).
var<private> guide_found: bool;
var<private> guide_albedo: vec3<f32>;
var<private> guide_normal: vec3<f32>;

// The invocation's next path (path regeneration): no guide vertex yet, and zero if it finds none.
fn guides_begin() {
    guide_found = false;
    guide_albedo = vec3<f32>(0.0);
    guide_normal = vec3<f32>(0.0);
}

// A hit of the path travelling along `direction` on a surface of geometric normal `normal`: the
// guides' vertex unless an earlier one was, or its material is delta. The albedo is the colour the
// material reflects (a diffuse colour, a conductor's specular colour) and an emitter's radiance,
// clamped to the [0, 1] the denoiser takes; the normal faces the incoming ray.
fn guide_vertex(material: Material, normal: vec3<f32>, direction: vec3<f32>) {
    if guide_found || material_is_delta(material) {
        return;
    }
    guide_found = true;
    guide_albedo = clamp(material.color, vec3<f32>(0.0), vec3<f32>(1.0));
    guide_normal = select(normal, -normal, dot(normal, direction) > 0.0);
}

// The guides of a sample the image kept; a sample it dropped as non-finite (accumulate_sample)
// drops its guides too, so the guides' means are over the image's samples.
fn accumulate_guides(pixel: u32, radiance: vec3<f32>) {
    if !is_finite_vec3(radiance) {
        return;
    }
    guide_sums[2u * pixel] = accumulate_sample(guide_sums[2u * pixel], guide_albedo);
    guide_sums[2u * pixel + 1u] = accumulate_sample(guide_sums[2u * pixel + 1u], guide_normal);
}
