"""The Owen-scrambled Sobol sampler's points (`sobol_point_2d`, `sobol_point_1d`, in numpy and WGSL):
the GPU draws the numpy reference's points bit for bit, so the statistics checked here on millions
of numpy points hold for the renderer's.

Stratification is exact (Sobol's (0, 2)-sequence property survives nested uniform scrambling and
the block-preserving shuffle); uniformity and independence are chi-square tests, one Sidak family
per test function."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest

from wgputrace.render import sobol
from wgputrace.testing.harness import run_kernel
from wgputrace.testing.stats import chi_square, sidak

SIGNIFICANCE = 1e-4
# A 16 x 16 grid: 4,096 points expect 16 in each cell.
GRID = 16
LARGEST_PREFIX_BITS = 12
# The draws of a path's first two vertices: camera 2D (0), light 2D + 2D (1, 2), BSDF 2D + 1D
# (3, 4), roulette 1D (5), and the second vertex's light 2D (6); then one draw deep in a long path.
DRAWS = (0, 1, 2, 3, 4, 5, 6, 61)
SEEDS = (0, 1, 0x9E3779B9, 0xFFFFFFFF)


def sobol_reference(index: np.ndarray, direction_numbers: list[int]) -> np.ndarray:
    """The textbook construction: XOR of the direction numbers of the index's set bits."""
    result = np.zeros(len(index), dtype=np.uint32)
    for bit, number in enumerate(direction_numbers):
        result ^= np.where((index >> np.uint32(bit)) & np.uint32(1), np.uint32(number), np.uint32(0))
    return result


def dimension_1_direction_numbers() -> list[int]:
    """Sobol's second dimension (primitive polynomial x + 1): v_k = v_(k-1) ^ (v_(k-1) >> 1)."""
    numbers = [1 << 31]
    for _ in range(31):
        numbers.append(numbers[-1] ^ (numbers[-1] >> 1))
    return numbers


def test_dimensions_are_sobols_first_two():
    index = np.concatenate([np.arange(1 << 14), np.random.default_rng(5).integers(0, 2**32, 10_000)]).astype(np.uint32)
    van_der_corput = [1 << (31 - bit) for bit in range(32)]
    assert np.array_equal(sobol.sobol_dimension_0(index), sobol_reference(index, van_der_corput))
    assert np.array_equal(sobol.sobol_dimension_1(index), sobol_reference(index, dimension_1_direction_numbers()))


def test_reverse_bits_mirrors_the_word():
    values = np.random.default_rng(6).integers(0, 2**32, 1000, dtype=np.uint64)
    expected = [int(f"{int(v):032b}"[::-1], 2) for v in values]
    assert sobol.reverse_bits(values.astype(np.uint32)).tolist() == expected


def elementary_cells(points: np.ndarray, x_bits: int, y_bits: int) -> np.ndarray:
    """The index of the elementary interval of 2^x_bits x 2^y_bits cells holding each point."""
    column = (points[:, 0] * (1 << x_bits)).astype(np.int64)
    row = (points[:, 1] * (1 << y_bits)).astype(np.int64)
    return (row << x_bits) + column


@pytest.mark.parametrize("seed", SEEDS)
def test_power_of_two_blocks_have_one_point_per_elementary_interval(seed):
    """A pixel's first 2^m samples, and every later aligned block of 2^m (16 + 16 samples: the
    second 16 too), put one point in each elementary interval of area 2^-m, of every shape, in
    every draw; 1D draws one point in each interval of length 2^-m."""
    for draw in DRAWS:
        for bits in range(1, LARGEST_PREFIX_BITS + 1):
            count = 1 << bits
            for start in (0, count):
                index = np.arange(start, start + count, dtype=np.uint32)
                points = sobol.sample_2d(seed, index, draw)
                for x_bits in range(bits + 1):
                    cells = elementary_cells(points, x_bits, bits - x_bits)
                    assert len(np.unique(cells)) == count, (draw, start, count, x_bits)
                line = (sobol.sample_1d(seed, index, draw) * count).astype(np.int64)
                assert len(np.unique(line)) == count, (draw, start, count)


def grid_counts(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    cells = (np.floor(x * GRID).astype(np.int64) * GRID) + np.floor(y * GRID).astype(np.int64)
    return np.bincount(cells, minlength=GRID * GRID)


def uniform_p_value(x: np.ndarray, y: np.ndarray) -> float:
    counts = grid_counts(x, y)
    return chi_square(counts, np.full(GRID * GRID, len(x) / GRID**2)).p_value


def test_coordinates_used_together_are_uniform_over_seeds():
    """Over 4,096 pixel seeds, sample `index` is uniform in every pair of coordinates a path uses
    together: a draw's two (the scramble randomises each point, what the estimator's unbiasedness
    rests on) and those of different draws (camera and light, the light's two 2D draws, the BSDF's
    2D and 1D, ...: the shuffles leave no correlation between draws). Within one pixel the pairs of
    different draws are not independent (a 2^m block of samples puts its points in sibling
    intervals in every draw at once), so the test is across pixels, as the image averages them."""
    seeds = sobol.pixel_sobol_states(7, 1 << LARGEST_PREFIX_BITS)[:, 0]
    pairs = [(draw, draw) for draw in DRAWS] + list(pairwise(DRAWS)) + [(0, 3), (1, 6)]
    axes = ((0, 1), (0, 0), (1, 0), (1, 1))
    tests = [
        (index, pair, axis)
        for index in (0, 1, 5, 1000)
        for pair in pairs
        for axis in axes
        if pair[0] != pair[1] or axis == (0, 1)
    ]
    level = sidak(SIGNIFICANCE, len(tests))
    for index, (first, second), (axis_a, axis_b) in tests:
        a = sobol.sample_2d(seeds, np.uint32(index), first)[:, axis_a]
        b = sobol.sample_2d(seeds, np.uint32(index), second)[:, axis_b]
        assert uniform_p_value(a, b) > level, (index, first, second, axis_a, axis_b)


def test_user_seeds_and_replicates_scramble_independently():
    """The same sample and draw of every pixel under two user seeds, or two replicates (resets) of
    one seed, are independent: pairs of them are uniform in the square, and no pixel's seed repeats."""
    pixels = 1 << LARGEST_PREFIX_BITS
    states = {
        "seed 1": sobol.pixel_sobol_states(1, pixels),
        "seed 2": sobol.pixel_sobol_states(2, pixels),
        "seed 1, replicate 1": sobol.pixel_sobol_states(1, pixels, replicate=1),
    }
    assert np.array_equal(states["seed 1"], sobol.pixel_sobol_states(1, pixels))
    comparisons = [("seed 1", "seed 2"), ("seed 1", "seed 1, replicate 1")]
    tests = [(pair, index, draw) for pair in comparisons for index in (0, 3) for draw in (0, 4)]
    level = sidak(SIGNIFICANCE, len(tests))
    for (first, second), index, draw in tests:
        a = sobol.sample_1d(states[first][:, 0], np.uint32(index), draw)
        b = sobol.sample_1d(states[second][:, 0], np.uint32(index), draw)
        assert uniform_p_value(a, b) > level, (first, second, index, draw)
    for state in states.values():
        assert len(np.unique(state[:, 0])) > pixels - 4  # 32-bit seeds: a collision or two at most
        assert not state[:, 1:].any()  # no samples taken


def test_points_are_in_the_unit_square():
    index = np.concatenate([np.arange(1 << 16), np.uint32(0xFFFFFFFF) - np.arange(1 << 10)]).astype(np.uint32)
    for seed in SEEDS:
        points = sobol.sample_2d(seed, index, 3)
        assert np.all(np.isfinite(points)) and points.min() >= 0.0 and points.max() < 1.0


GPU_KERNEL = """
//! include "sampling/sobol_points.wgsl"
fn compute(i: u32) -> vec4<u32> {
    let input = inputs_0[i];
    let draw_seed = sobol_seed(input.x, input.z);
    let point = sobol_point_2d(input.y, draw_seed);
    let line = sobol_point_1d(input.y, draw_seed);
    return vec4<u32>(point, line, bitcast<u32>(sobol_unit(point.y)));
}
"""


def test_gpu_draws_the_reference_points(gpu_context):
    """The WGSL points and the numpy ones agree bit for bit: seeds, draws, indices from small to the
    top of the 32-bit range."""
    rng = np.random.default_rng(11)
    count = 20_000
    seeds = rng.integers(0, 2**32, count, dtype=np.uint64).astype(np.uint32)
    index = np.concatenate([np.arange(count // 2), rng.integers(0, 2**32, count - count // 2)]).astype(np.uint32)
    draws = rng.integers(0, 200, count).astype(np.uint32)
    inputs = np.stack([seeds, index, draws, np.zeros(count, np.uint32)], axis=1)
    gpu = run_kernel(
        gpu_context, GPU_KERNEL, [inputs], np.uint32, 4 * count, input_types=["vec4<u32>"], output_type="vec4<u32>"
    ).reshape(count, 4)
    draw_seeds = sobol.sobol_seed(seeds, draws)
    x, y = sobol.sobol_point_2d(index, draw_seeds)
    assert np.array_equal(gpu[:, 0], x)
    assert np.array_equal(gpu[:, 1], y)
    assert np.array_equal(gpu[:, 2], sobol.sobol_point_1d(index, draw_seeds))
    assert np.array_equal(gpu[:, 3].view(np.float32), sobol.unit(y))
