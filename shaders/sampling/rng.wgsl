// Per-pixel random numbers: xoshiro128** (Blackman & Vigna), 128 bits of state, period 2^128 - 1.

// The state lives in a private variable during one invocation; the kernel loads it from and
// stores it back to the per-pixel state buffer, so successive dispatches continue the sequence.
var<private> rng_state: vec4<u32>;

fn rotate_left(x: u32, k: u32) -> u32 {
    return (x << k) | (x >> (32u - k));
}

fn rng_next_u32() -> u32 {
    let s = rng_state;
    let result = rotate_left(s.y * 5u, 7u) * 9u;
    let t = s.y << 9u;
    var n = s;
    n.z ^= n.x;
    n.w ^= n.y;
    n.y ^= n.z;
    n.x ^= n.w;
    n.z ^= t;
    n.w = rotate_left(n.w, 11u);
    rng_state = n;
    return result;
}

// Uniform in [0, 1): the top 24 bits, exactly representable in f32.
fn rng_next_f32() -> f32 {
    return f32(rng_next_u32() >> 8u) * (1.0 / 16777216.0);
}

fn rng_next_2d() -> vec2<f32> {
    let x = rng_next_f32();
    return vec2<f32>(x, rng_next_f32());
}
