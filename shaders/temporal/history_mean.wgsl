// A pixel history's mean radiance.
//
// The including kernel declares TemporalPixel (generated: TEMPORAL_PIXEL).

// The mean of `old`'s samples; black where it holds none. A length may be fractional: upsampled
// histories count interpolated samples as a part of one (INTERPOLATED_SAMPLE_WEIGHT).
fn history_mean(old: TemporalPixel) -> vec3<f32> {
    let total = old.sum.xyz - old.compensation.xyz;
    return select(vec3<f32>(0.0), total / old.length, old.length > 0.0);
}
