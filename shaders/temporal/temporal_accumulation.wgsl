// Temporal accumulation: this frame's samples added to each pixel's history, reprojected along the G-buffer's motion while anything moves.
//! include "temporal/history.wgsl"
//! include "generated/bindings/temporal.wgsl"
//
// The history is a Kahan sum of radiance and its length in samples, so a frame's samples are
// added exactly as the renderer's accumulation adds them (accumulate_sample): while nothing moves
// the history is taken as it is and its mean is the plain mean of every sample since it began.
// While something moves, the history is rebuilt from the previous one at the point each pixel's
// first hit was (bilinear taps that pass the depth, normal and surface tests), demodulated by the
// taps' albedo and remodulated by this pixel's, its length capped at params.length_cap and its
// mean clamped to this frame's neighbourhood (temporal_accumulation.py says why).

// The previous history where this pixel's first hit was, or none (the pixel starts again) where
// no tap passes; the history then shows this frame's G-buffer (add_frame keeps it).
fn reprojected(xy: vec2<i32>, here: GBufferPixel) -> Reprojection {
    let taps = passing_taps(xy, here, depth_tolerance(here, depth_gradient(xy, here), 0.0));
    if !(taps.weights > 0.0) {
        return Reprojection(no_history(), here);
    }
    return Reprojection(reprojected_history(taps, neighbourhood(xy, 1), here.albedo), here);
}

fn history_pass(xy: vec2<i32>, pixel: u32) {
    let here = gbuffer[pixel];
    history[pixel] = with_frame(previous(xy, here).history, xy);
}
