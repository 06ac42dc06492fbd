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

// The previous frame's reservoir of a surface, and its receiver shaded again.
struct PreviousReservoir {
    reservoir: PixelReservoir,
    receiver: ShadedPoint,
}

// The previous frame's reservoir of the surface `point` (seen at `pixel`), moved along the
// pixel's motion vector; empty (M 0) where the previous camera did not see it, the reprojected
// pixel lies outside the image, or its receiver does not suit `point`.
fn previous_reservoir(point: ShadedPoint, pixel: u32) -> PreviousReservoir {
    let empty = PixelReservoir(no_resampled_light(), 0.0, ReservoirReceiver(vec3<f32>(0.0), NO_TRIANGLE, vec3<f32>(0.0), 0.0));
    let none = PreviousReservoir(empty, point);
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
    if previous.receiver.count <= 0.0 {
        return none;
    }
    let receiver = receiver_point(previous.receiver);
    if !suits(point, receiver) {
        return none;
    }
    return PreviousReservoir(previous, receiver);
}

// The share of `sample` (its target `here` at this point) that comes from the previous frame's
// reservoir (`previous`) or this frame's: its target times confidence at that reservoir's receiver
// over the sum at both (`history`: the previous reservoir's confidence, in candidates).
fn temporal_share(sample: ResampledLight, here: f32, receiver: ShadedPoint, history: f32, previous: bool) -> f32 {
    let there = history * target_at(receiver, sample);
    let this_frame = f32(RESAMPLED_LIGHT_CANDIDATES) * here;
    let total = there + this_frame;
    return select(0.0, select(this_frame, there, previous) / total, total > 0.0);
}

fn vertex_reservoir(point: ShadedPoint, pixel: u32) -> VertexReservoir {
    let fresh = candidate_reservoir(point);
    let count = f32(RESAMPLED_LIGHT_CANDIDATES);
    var kept = fresh.kept;
    var weight = contribution_weight(fresh) / count;
    var confidence = count;
    let found = previous_reservoir(point, pixel);
    let previous = found.reservoir;
    if previous.receiver.count > 0.0 {
        let history = min(previous.receiver.count, RESERVOIR_HISTORY_CAP * count);
        let receiver = found.receiver;
        var combined = empty_light_reservoir();
        // drawn at 0: kept wherever its weight is positive
        let own_share = temporal_share(kept, kept.target_value, receiver, history, false);
        reservoir_update(&combined, kept, own_share * kept.target_value * weight, 0.0);
        // the previous sample, seen from here
        let moved = resampled_light(point, light_seen_from(previous.sample, point.p), previous.sample.index);
        let old_share = temporal_share(previous.sample, moved.target_value, receiver, history, true);
        let old_weight = old_share * moved.target_value * previous.weight;
        let u_keep = sample_1d();
        if old_weight > 0.0 && old_weight <= FLOAT_MAX {
            reservoir_update(&combined, moved, old_weight, u_keep);
        }
        kept = combined.kept;
        weight = contribution_weight(combined);
        confidence = count + history;
        if RESERVOIR_CHECK_WEIGHT_SUMS && kept.target_value > 0.0 {
            // the survivor's shares as this frame's sample and as the previous reservoir would hold it
            let held = stored_light(reservoir_record(kept, 0.0));
            let here = resampled_light(point, light_seen_from(held, point.p), held.index).target_value;
            let sum = temporal_share(kept, kept.target_value, receiver, history, false) + temporal_share(held, here, receiver, history, true);
            checked_weight_sum(sum, 2u);
        }
    }
    restir_reservoirs[pixel] = reservoir_record(kept, weight);
    // its confidence even where it holds no light: whether the next frame takes it must not depend
    // on what it drew, or the weights of this frame's samples would not sum to one on average
    restir_receivers[pixel] = ReservoirReceiver(point.p, point.triangle_index, point.towards_viewer, confidence);
    return VertexReservoir(kept, weight, confidence);
}
