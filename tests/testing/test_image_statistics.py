"""The statistics behind the reference tests: block tests hold their significance on noise with a
known answer and find a shifted block; downsampling and noise-free blocks."""

from __future__ import annotations

import math

import numpy as np

from wgputrace.testing.image_statistics import Estimate, compare_blocks
from wgputrace.testing.stats import sidak


def test_block_test_rejects_at_its_nominal_rate_on_pure_noise():
    """Two noisy images of the same picture (pixel variances spread over three orders of magnitude,
    as in renders): the fraction of block tests rejected at level a is near a, and a shift of a few
    standard errors in one block is found."""
    rng = np.random.default_rng(20261123)
    size, block, batches, level = 64, 8, 16, 0.05
    picture = rng.uniform(0.1, 1.0, (size, size, 3))
    sigma = picture * 10.0 ** rng.uniform(-1.5, 0.0, (size, size, 3))
    ours = Estimate.from_batches(picture + sigma * rng.standard_normal((batches, size, size, 3)))
    reference = Estimate(picture + 0.1 * sigma * rng.standard_normal((size, size, 3)), (0.1 * sigma) ** 2, 15.0)
    comparison = compare_blocks(ours, reference, block)
    tests = comparison.p_value.size
    rejected = np.count_nonzero(comparison.p_value < level)
    # binomial(tests, level): mean 9.6, standard deviation 3.0 for 192 tests
    assert abs(rejected - level * tests) < 4.0 * math.sqrt(tests * level * (1 - level)), rejected

    shifted = Estimate(ours.mean.copy(), ours.variance, ours.dof)
    shifted.mean[:block, :block, 0] += 6.0 * comparison.standard_error[0, 0, 0]
    assert compare_blocks(shifted, reference, block).p_value[0, 0, 0] < sidak(1e-3, tests)


def test_downsampling_averages_and_divides_variance():
    mean = np.arange(16.0).reshape(4, 4, 1).repeat(3, axis=2)
    estimate = Estimate(mean, np.ones_like(mean), 7.0).downsampled(2)
    np.testing.assert_array_equal(estimate.mean[..., 0], [[2.5, 4.5], [10.5, 12.5]])
    np.testing.assert_array_equal(estimate.variance, np.full((2, 2, 3), 0.25))


def test_noise_free_blocks_pass_only_when_equal():
    zero = Estimate(np.zeros((8, 8, 3)), np.zeros((8, 8, 3)), math.inf)
    other = Estimate(np.zeros((8, 8, 3)), np.zeros((8, 8, 3)), math.inf)
    assert np.all(compare_blocks(zero, other, 8).p_value == 1.0)
    other.mean[0, 0, 0] = 1e-6
    assert compare_blocks(zero, other, 8).p_value[0, 0, 0] == 0.0
