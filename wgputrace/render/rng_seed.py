"""Per-pixel random-number states, derived from the user's seed and the pixel index."""

from __future__ import annotations

import numpy as np

_GOLDEN_GAMMA = np.uint64(0x9E3779B97F4A7C15)


def _splitmix64(x: np.ndarray) -> np.ndarray:
    """SplitMix64's output function: decorrelates nearby integers (seed, pixel) into 64 random bits."""
    z = x + _GOLDEN_GAMMA
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def pixel_rng_states(seed: int, pixel_count: int) -> np.ndarray:
    """(pixel_count, 4) uint32 xoshiro128** states; never all zero (xoshiro's one bad state)."""
    with np.errstate(over="ignore"):
        base = _splitmix64(np.array([seed & 0xFFFFFFFFFFFFFFFF], dtype=np.uint64))[0]
        pixels = np.arange(pixel_count, dtype=np.uint64) * np.uint64(2)
        low = _splitmix64(base + pixels)
        high = _splitmix64(base + pixels + np.uint64(1))
    states = np.stack([low, high], axis=1).view(np.uint32).reshape(pixel_count, 4).copy()
    states[~states.any(axis=1), 0] = 1
    return states
