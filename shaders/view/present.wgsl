// Presenting a frame: the resolved linear image scaled to the window, exposure, tone curve, and the text overlay.
//! include "generated/view_structs.wgsl"
//! include "view/tone_curves.wgsl"
//! include "generated/bindings/present.wgsl"
//
// Writes linear values: the target is an sRGB format whose hardware encodes them, unless
// ENCODE_SRGB says the target is plain unorm (then this shader encodes).

override ENCODE_SRGB: bool = false;

@vertex
fn vertex_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    // one triangle covering the whole target
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.0, 1.0);
}

fn srgb_encode(linear: vec3<f32>) -> vec3<f32> {
    let low = linear * 12.92;
    let high = 1.055 * pow(linear, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, linear <= vec3<f32>(0.0031308));
}

@fragment
fn fragment_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let target_pixel = vec2<u32>(position.xy);
    // nearest neighbour: a reduced-resolution frame shows its pixels as blocks, honestly
    let source = min(
        target_pixel * vec2<u32>(params.image_width, params.image_height) / vec2<u32>(params.target_width, params.target_height),
        vec2<u32>(params.image_width - 1u, params.image_height - 1u),
    );
    let value = textureLoad(image, source, 0);
    var exposure = params.exposure;
    if params.auto_exposure != 0u && exposure_state[0].y != 0.0 {
        exposure *= MIDDLE_GREY / exp(exposure_state[0].x);
    }
    var color = tone_curve(value.xyz * exposure, params.tonemap);
    let in_overlay = target_pixel - vec2<u32>(params.overlay_x, params.overlay_y);
    if params.overlay_visible != 0u && all(target_pixel >= vec2<u32>(params.overlay_x, params.overlay_y))
        && all(in_overlay < textureDimensions(overlay)) {
        let text = textureLoad(overlay, in_overlay, 0);
        color = mix(color, text.xyz, text.w);
    }
    if ENCODE_SRGB {
        color = srgb_encode(color);
    }
    return vec4<f32>(color, 1.0);
}
