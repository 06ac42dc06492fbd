// A pixel history's mean radiance.
//
// The including kernel declares TemporalPixel (generated: TEMPORAL_PIXEL).

// The mean of `old`'s samples; black where it holds none (a history holds at least one sample or
// none, so max keeps every other mean as it is).
fn history_mean(old: TemporalPixel) -> vec3<f32> {
    return (old.sum.xyz - old.compensation.xyz) / max(old.length, 1.0);
}
