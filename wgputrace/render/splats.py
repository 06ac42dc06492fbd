"""Light tracing's splat buffer (shaders/integrators/bdpt/splat.wgsl), which only the bidirectional path tracer
binds: per pixel a 64-bit fixed-point sum per colour channel, summed with integer atomics so that
the order invocations add in cannot change a bit, and a count of splats refused."""

from __future__ import annotations

import numpy as np

# u32 words per pixel: (low, high) per channel, the refused count, one unused (16-byte rows)
SPLAT_WORDS = 8
# Fixed-point scale: a splat's value is rounded to a multiple of 2^-24 (integrators/bdpt/splat.wgsl SPLAT_SCALE).
SPLAT_SCALE = 2.0**24
_REFUSED = 6


def zeroed_splats(pixels: int) -> np.ndarray:
    return np.zeros(pixels * SPLAT_WORDS, dtype=np.uint32)


def splat_sums(words: np.ndarray) -> np.ndarray:
    """float64 (n, 3): the radiance splatted into each of n pixels, summed over all samples."""
    rows = words.reshape(-1, SPLAT_WORDS).astype(np.float64)
    return (rows[:, 0:6:2] + rows[:, 1:6:2] * 2.0**32) / SPLAT_SCALE


def refused_splats(words: np.ndarray) -> int:
    """Splats dropped for a non-finite or out-of-range value, over all pixels."""
    return int(words.reshape(-1, SPLAT_WORDS)[:, _REFUSED].astype(np.int64).sum())
