// One frame's picture as linear colour: the accumulated mean (blended with the filtered one) or a guide view.
//! include "generated/structs.wgsl"
//! include "generated/view_structs.wgsl"
//! include "generated/display_constants.wgsl"
//! include "common/constants.wgsl"
//! include "view/colormap.wgsl"
//! include "view/guide_packing.wgsl"
//! include "generated/bindings/resolve.wgsl"
//! include "generated/workgroup.wgsl"

// The mean of a pixel's samples. Rows above `rows_done` already have the current band pass's
// sample. The Kahan compensation is left out: it is below half an ulp of the sum, invisible in a
// picture, and reading it would double this kernel's storage loads (slow on CPU adapters). A
// pixel with no sample yet shows the fallback image (the last reduced-resolution frame, scaled
// up) if there is one, with alpha 0: the filter takes nothing from it.
fn mean_radiance(pixel: vec2<u32>) -> vec4<f32> {
    let count = params.samples_per_pixel + select(0u, 1u, pixel.y < params.rows_done);
    if count == 0u {
        if params.fallback_width == 0u {
            return vec4<f32>(0.0);
        }
        let size = vec2<u32>(params.fallback_width, params.fallback_height);
        return vec4<f32>(textureLoad(fallback, pixel * size / vec2<u32>(params.width, params.height), 0).xyz, 0.0);
    }
    return vec4<f32>(accumulation[pixel.y * params.width + pixel.x].sum.xyz / f32(count), 1.0);
}

fn demodulation_albedo(guide: Guide) -> vec3<f32> {
    return max(guide.albedo, vec3<f32>(FILTER_ALBEDO_MIN));
}

// Invocation (x, y) resolves pixel (x, first_row + y): frames that added a band of rows
// resolve only those.
@compute @workgroup_size(WORKGROUP_X, WORKGROUP_Y)
fn main(@builtin(global_invocation_id) invocation: vec3<u32>) {
    let id = vec2<u32>(invocation.x, invocation.y + params.first_row);
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    var color = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    switch params.view {
        case VIEW_RADIANCE: {
            color = mean_radiance(id);
            if params.mode != RESOLVE_MEAN {
                // the filter smooths lighting, not texture: it works on radiance over albedo
                let albedo = demodulation_albedo(unpack_guide(textureLoad(guides, id, 0)));
                let demodulated = color.xyz / albedo;
                if params.mode == RESOLVE_DEMODULATED {
                    color = vec4<f32>(demodulated, color.w);
                } else {
                    let smoothed = textureLoad(filtered, id, 0).xyz;
                    color = vec4<f32>(albedo * mix(demodulated, smoothed, params.filter_weight), color.w);
                }
            }
        }
        case VIEW_NORMAL: {
            let guide = unpack_guide(textureLoad(guides, id, 0));
            color = vec4<f32>(select(vec3<f32>(0.0), guide.normal * 0.5 + 0.5, guide.depth > 0.0), 1.0);
        }
        case VIEW_ALBEDO: {
            color = vec4<f32>(unpack_guide(textureLoad(guides, id, 0)).albedo, 1.0);
        }
        case VIEW_DEPTH: {
            // near is bright; `depth_scale` (the scene's diagonal) maps to black
            let depth = unpack_guide(textureLoad(guides, id, 0)).depth;
            color = vec4<f32>(vec3<f32>(select(0.0, 1.0 - min(depth / params.depth_scale, 1.0), depth > 0.0)), 1.0);
        }
        case VIEW_HEAT: {
            let steps = unpack_guide(textureLoad(guides, id, 0)).steps;
            color = vec4<f32>(heat_color(log2(f32(steps) + 1.0) / params.heat_log2_max), 1.0);
        }
        default: {}
    }
    textureStore(resolved, id, color);
}
