"""The Owen-scrambled Sobol sampler on the host: the per-pixel states the renderer uploads, and the
points the WGSL `sobol_point_2d` and friends draw, in the same uint32 arithmetic (the tests compare
the two, and check the points' statistics here, where millions of them are cheap).

A pixel's state is (seed, samples taken, 0, 0). Its seed comes from the user's seed and the pixel
(`pixel_rng_states`' SplitMix64 words) and from the replicate: the renderer's `reset` starts a new
replicate, an independent scramble, so images made after resets are independent estimates.
"""

from __future__ import annotations

import numpy as np

from .rng_seed import pixel_rng_states

_UNIT = 1.0 / 16777216.0


def _u32(x: np.ndarray | int) -> np.ndarray:
    return np.asarray(x, dtype=np.uint32)


def sobol_hash(value: np.ndarray | int) -> np.ndarray:
    """Wellons' lowbias32, as the WGSL `sobol_hash`."""
    x = _u32(value)
    with np.errstate(over="ignore"):
        x = x ^ (x >> np.uint32(16))
        x = x * np.uint32(0x7FEB352D)
        x = x ^ (x >> np.uint32(15))
        x = x * np.uint32(0x846CA68B)
        return x ^ (x >> np.uint32(16))


def sobol_seed(seed: np.ndarray | int, part: np.ndarray | int) -> np.ndarray:
    """The WGSL `sobol_seed`: the seed of part `part` of what `seed` seeds."""
    return sobol_hash(_u32(seed) ^ sobol_hash(part))


def reverse_bits(value: np.ndarray | int) -> np.ndarray:
    """WGSL's reverseBits on uint32."""
    x = _u32(value)
    for shift, mask in ((1, 0x55555555), (2, 0x33333333), (4, 0x0F0F0F0F), (8, 0x00FF00FF)):
        x = ((x >> np.uint32(shift)) & np.uint32(mask)) | ((x & np.uint32(mask)) << np.uint32(shift))
    return (x >> np.uint32(16)) | (x << np.uint32(16))


def laine_karras_permutation(value: np.ndarray | int, seed: np.ndarray | int) -> np.ndarray:
    """The WGSL `laine_karras_permutation` (Vegdahl's constants)."""
    x, seed = _u32(value), _u32(seed)
    with np.errstate(over="ignore"):
        x = x ^ (x * np.uint32(0x3D20ADEA))
        x = x + seed
        x = x * ((seed >> np.uint32(16)) | np.uint32(1))
        x = x ^ (x * np.uint32(0x05526C56))
        return x ^ (x * np.uint32(0x53A22864))


def nested_uniform_scramble(value: np.ndarray | int, seed: np.ndarray | int) -> np.ndarray:
    return reverse_bits(laine_karras_permutation(reverse_bits(value), seed))


def sobol_dimension_0(index: np.ndarray | int) -> np.ndarray:
    return reverse_bits(index)


def sobol_dimension_1(index: np.ndarray | int) -> np.ndarray:
    """The WGSL `sobol_dimension_1`, loop-free (the tests check it against the direction numbers)."""
    digits = _u32(index)
    for shift, mask in ((1, 0x55555555), (2, 0x33333333), (4, 0x0F0F0F0F), (8, 0x00FF00FF), (16, 0x0000FFFF)):
        digits = digits ^ ((digits >> np.uint32(shift)) & np.uint32(mask))
    return reverse_bits(digits)


def sobol_point_2d(index: np.ndarray | int, draw_seed: np.ndarray | int) -> tuple[np.ndarray, np.ndarray]:
    """The uint32 coordinates of point `index` of the 2D sequence of `draw_seed`."""
    shuffled = nested_uniform_scramble(index, draw_seed)
    x = nested_uniform_scramble(sobol_dimension_0(shuffled), sobol_seed(draw_seed, 1))
    y = nested_uniform_scramble(sobol_dimension_1(shuffled), sobol_seed(draw_seed, 2))
    return x, y


def sobol_point_1d(index: np.ndarray | int, draw_seed: np.ndarray | int) -> np.ndarray:
    shuffled = nested_uniform_scramble(index, draw_seed)
    return nested_uniform_scramble(sobol_dimension_0(shuffled), sobol_seed(draw_seed, 1))


def unit(bits: np.ndarray) -> np.ndarray:
    """float32 in [0, 1) from the top 24 bits, as sobol_unit."""
    return ((bits >> np.uint32(8)).astype(np.float32) * np.float32(_UNIT)).astype(np.float32)


def sample_2d(pixel_seed: np.ndarray | int, index: np.ndarray | int, draw: np.ndarray | int) -> np.ndarray:
    """float32 (..., 2): what sample_2d returns as draw number `draw` of sample `index` of the
    pixel seeded `pixel_seed` (the Sobol sampler's WGSL `sample_2d`)."""
    x, y = sobol_point_2d(index, sobol_seed(pixel_seed, draw))
    return np.stack([unit(x), unit(y)], axis=-1)


def sample_1d(pixel_seed: np.ndarray | int, index: np.ndarray | int, draw: np.ndarray | int) -> np.ndarray:
    """float32: what sample_1d returns as draw number `draw` of sample `index`."""
    return unit(sobol_point_1d(index, sobol_seed(pixel_seed, draw)))


def pixel_sobol_states(seed: int, pixel_count: int, replicate: int = 0) -> np.ndarray:
    """(pixel_count, 4) uint32: each pixel's seed for `replicate` of the user's `seed`, no samples taken."""
    words = pixel_rng_states(seed, pixel_count)[:, 0]
    states = np.zeros((pixel_count, 4), dtype=np.uint32)
    states[:, 0] = sobol_seed(words, replicate)
    return states
