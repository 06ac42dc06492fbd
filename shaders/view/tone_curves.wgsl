// The tone curves of wgputrace.image_io (tone_curve): exposed linear sRGB to display-linear values in [0, 1].
//! include "generated/display_constants.wgsl"
//
// Each is its numpy curve line for line (the constants and their sources: image_io, generated
// into view_structs.wgsl); tests/view/test_tone_curves.py holds the two to one another.

fn tone_clip(c: vec3<f32>) -> vec3<f32> {
    return clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Khronos PBR Neutral: darks offset by up to F90, highlights compressed from
// PBR_NEUTRAL_COMPRESSION_START towards white along the line to it (no hue shift).
fn tone_pbr_neutral(color: vec3<f32>) -> vec3<f32> {
    let x = min(color.r, min(color.g, color.b));
    let offset = select(PBR_NEUTRAL_F90, x - x * x / (4.0 * PBR_NEUTRAL_F90), x < 2.0 * PBR_NEUTRAL_F90);
    let c = color - offset;
    let peak = max(c.r, max(c.g, c.b));
    if peak < PBR_NEUTRAL_COMPRESSION_START {
        return c;
    }
    let d = 1.0 - PBR_NEUTRAL_COMPRESSION_START;
    let new_peak = 1.0 - d * d / (peak + d - PBR_NEUTRAL_COMPRESSION_START);
    let g = 1.0 - 1.0 / (PBR_NEUTRAL_DESATURATION * (peak - new_peak) + 1.0);
    return mix(c * (new_peak / peak), vec3<f32>(new_peak), g);
}

// Horner's rule over AGX_SIGMOID, highest power first.
fn agx_sigmoid(x: vec3<f32>) -> vec3<f32> {
    var y = vec3<f32>(AGX_SIGMOID[0]);
    for (var k = 1; k < 7; k++) {
        y = y * x + AGX_SIGMOID[k];
    }
    return y;
}

fn tone_agx(color: vec3<f32>) -> vec3<f32> {
    let v = AGX_INSET * max(SRGB_TO_REC2020 * color, vec3<f32>(0.0));
    let encoded = clamp((log2(max(v, vec3<f32>(AGX_FLOOR))) - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV), vec3<f32>(0.0), vec3<f32>(1.0));
    let display = AGX_OUTSET * agx_sigmoid(encoded);
    return clamp(REC2020_TO_SRGB * pow(max(display, vec3<f32>(0.0)), vec3<f32>(AGX_DISPLAY_GAMMA)), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn tone_aces(color: vec3<f32>) -> vec3<f32> {
    let v = ACES_INPUT * color;
    let fitted = (v * (v + ACES_FIT[0]) - ACES_FIT[1]) / (v * (ACES_FIT[2] * v + ACES_FIT[3]) + ACES_FIT[4]);
    return clamp(ACES_OUTPUT * fitted, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Tone curve `curve` (a TONEMAP_* id) of exposed linear radiance `exposed` (>= 0), limited to
// TONE_RADIANCE_MAX as the numpy curves are.
fn tone_curve(exposed: vec3<f32>, curve: u32) -> vec3<f32> {
    switch curve {
        case TONEMAP_PBR_NEUTRAL: {
            return tone_pbr_neutral(min(exposed, vec3<f32>(TONE_RADIANCE_MAX)));
        }
        case TONEMAP_AGX: {
            return tone_agx(min(exposed, vec3<f32>(TONE_RADIANCE_MAX)));
        }
        case TONEMAP_ACES: {
            return tone_aces(min(exposed, vec3<f32>(TONE_RADIANCE_MAX)));
        }
        default: {
            return tone_clip(exposed);
        }
    }
}

// Rec. 709 luminance of linear sRGB.
fn luminance(color: vec3<f32>) -> f32 {
    return dot(color, REC709_LUMINANCE);
}
