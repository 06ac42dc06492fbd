// A first vertex's reservoir combined with the one its surface had in the previous frame
// (vertex_reservoir), where render_frame traces the whole image and the restir integrator keeps
// its reservoirs from frame to frame (its G-buffer variant, RESERVOIR_HISTORY_CAP > 0). The
// previous frame's reservoir is the one of the pixel the G-buffer's motion vector points to,
// where its receiver suits this point (reservoir_records.wgsl); the two are combined by the
// generalised balance heuristic (GRIS), as the spatial reuse combines neighbours', each weighed
// by its confidence M, the previous one's capped at RESERVOIR_HISTORY_CAP frames' candidates so
// that what it learnt is renewed. The combination is this pixel's reservoir for the next frame.
//
// The Renderer hands the previous frame's reservoirs over only to a frame where the camera alone
// moved (render_frame): both reservoirs' targets are then evaluated in the scene they were drawn
// in, so every sample's weights sum to one over the reservoirs that could have given it, and the
// estimate is the direct light exactly. At rest each frame stands alone (the history's mean
// converges fastest from independent frames), and after any edit of the scene every pixel starts
// from its own candidates again: no moved or switched-off light is seen in a later frame.
//! include "generated/bindings/pixels.wgsl"
//! include "integrators/restir/reservoir_records.wgsl"

// The previous frame's reservoir of the surface `point` (seen at `pixel`), moved along the
// pixel's motion vector; empty (M 0) where the previous camera did not see it, the reprojected
// pixel lies outside the image, or its receiver does not suit `point`.
fn previous_reservoir(point: ShadedPoint, pixel: u32) -> PixelReservoir {
    let none = PixelReservoir(no_resampled_light(), 0.0, ReservoirReceiver(vec3<f32>(0.0), NO_TRIANGLE, vec3<f32>(0.0), 0.0));
    let seen = gbuffer[pixel];
    if !(seen.previous_depth > 0.0) {
        return none;
    }
    let xy = vec2<f32>(f32(pixel % frame.width), f32(pixel / frame.width));
    let at = vec2<i32>(round(xy + seen.motion));
    if any(at < vec2<i32>(0)) || at.x >= i32(frame.width) || at.y >= i32(frame.height) {
        return none;
    }
    let index = u32(at.y) * frame.width + u32(at.x);
    let previous = pixel_reservoir(previous_restir_reservoirs[index], previous_restir_receivers[index]);
    if previous.receiver.count <= 0.0 || !suits(point, receiver_point(previous.receiver)) {
        return none;
    }
    return previous;
}

fn vertex_reservoir(point: ShadedPoint, pixel: u32) -> VertexReservoir {
    let fresh = candidate_reservoir(point);
    let count = f32(RESAMPLED_LIGHT_CANDIDATES);
    var kept = fresh.kept;
    var weight = contribution_weight(fresh) / count;
    var confidence = count;
    let previous = previous_reservoir(point, pixel);
    if previous.receiver.count > 0.0 {
        let history = min(previous.receiver.count, RESERVOIR_HISTORY_CAP * count);
        let receiver = receiver_point(previous.receiver);
        var combined = empty_light_reservoir();
        // this frame's sample, against the previous receiver's target for it
        let own_there = history * target_at(receiver, kept);
        let own_here = count * kept.target_value;
        let own_share = select(0.0, own_here / (own_here + own_there), own_here > 0.0);
        // drawn at 0: kept wherever its weight is positive
        reservoir_update(&combined, kept, own_share * kept.target_value * weight, 0.0);
        // the previous sample, seen from here, against this point's target for it
        let moved = resampled_light(point, light_seen_from(previous.sample, point.p), previous.sample.index);
        let old_there = history * target_at(receiver, previous.sample);
        let old_share = select(0.0, old_there / (old_there + count * moved.target_value), old_there > 0.0);
        let old_weight = old_share * moved.target_value * previous.weight;
        let u_keep = sample_1d();
        if old_weight > 0.0 && old_weight <= FLOAT_MAX {
            reservoir_update(&combined, moved, old_weight, u_keep);
        }
        kept = combined.kept;
        weight = contribution_weight(combined);
        confidence = count + history;
    }
    restir_reservoirs[pixel] = reservoir_record(kept, weight);
    // its confidence even where it holds no light: whether the next frame takes it must not depend
    // on what it drew, or the weights of this frame's samples would not sum to one on average
    restir_receivers[pixel] = ReservoirReceiver(point.p, point.triangle_index, point.towards_viewer, confidence);
    return VertexReservoir(kept, weight, confidence);
}
