// Owen-scrambled Sobol points, after Burley's "Practical Hash-based Owen Scrambling" (JCGT 2020).
//
// The first two Sobol dimensions, scrambled by a hash that flips each bit by the bits above it
// (a nested uniform scramble, so every elementary interval a prefix of 2^m points stratifies
// keeps one point), and the sample index shuffled by the same kind of scramble, which permutes
// indices within aligned blocks of every power of two, so a pixel's first 2^m samples are still
// one whole block of the sequence. render.sobol is the same arithmetic in numpy (sobol_point_2d).

// Chris Wellons' lowbias32: decorrelates nearby integers (pixel seeds, draw numbers) into seeds.
fn sobol_hash(value: u32) -> u32 {
    var x = value;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// A seed for the part `part` of what `seed` seeds (a draw of a pixel, an axis of a draw).
fn sobol_seed(seed: u32, part: u32) -> u32 {
    return sobol_hash(seed ^ sobol_hash(part));
}

// Vegdahl's improvement of the Laine-Karras hash Burley uses ("Building a better LK hash", 2021):
// each step changes a bit only by the bits below it, which is what makes the scramble nested.
fn laine_karras_permutation(value: u32, seed: u32) -> u32 {
    var x = value;
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Bit 31 is the first binary digit of the point: reversed, the hash flips each digit by the
// digits before it.
fn nested_uniform_scramble(value: u32, seed: u32) -> u32 {
    return reverseBits(laine_karras_permutation(reverseBits(value), seed));
}

// Sobol dimension 0, the van der Corput sequence: the index's bits mirrored into the fraction.
fn sobol_dimension_0(index: u32) -> u32 {
    return reverseBits(index);
}

// Sobol dimension 1: fraction digit j is the parity of the index bits k with binomial(k, j) odd,
// which by Lucas' theorem are the k whose bits include j's; five butterfly steps sum over those
// supersets without a loop (llvmpipe's loop budget is per invocation, shared with the traversal).
fn sobol_dimension_1(index: u32) -> u32 {
    var digits = index;
    digits ^= (digits >> 1u) & 0x55555555u;
    digits ^= (digits >> 2u) & 0x33333333u;
    digits ^= (digits >> 4u) & 0x0f0f0f0fu;
    digits ^= (digits >> 8u) & 0x00ff00ffu;
    digits ^= (digits >> 16u) & 0x0000ffffu;
    return reverseBits(digits);
}

// Uniform in [0, 1): the top 24 bits, exactly representable in f32 (as rng_next_f32).
fn sobol_unit(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

// Point `index` of the scrambled, shuffled 2D Sobol sequence of `draw_seed`: every draw of a path
// takes the same two dimensions under its own seed (padding by independent shuffles, as Burley
// does), so each draw is a (0, 2)-sequence in its own right.
fn sobol_point_2d(index: u32, draw_seed: u32) -> vec2<u32> {
    let shuffled = nested_uniform_scramble(index, draw_seed);
    let x = nested_uniform_scramble(sobol_dimension_0(shuffled), sobol_seed(draw_seed, 1u));
    let y = nested_uniform_scramble(sobol_dimension_1(shuffled), sobol_seed(draw_seed, 2u));
    return vec2<u32>(x, y);
}

// The 1D draw: the first coordinate of its own 2D sequence.
fn sobol_point_1d(index: u32, draw_seed: u32) -> u32 {
    let shuffled = nested_uniform_scramble(index, draw_seed);
    return nested_uniform_scramble(sobol_dimension_0(shuffled), sobol_seed(draw_seed, 1u));
}
