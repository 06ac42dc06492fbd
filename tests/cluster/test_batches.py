"""Batches and their merge, without a cluster: the batch plan depends on the samples and the seed
alone, and the merged image on nothing but the batches."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.cluster.batches import DEFAULT_BATCHES, batch_seed, split_samples
from wgputrace.cluster.merge import BatchImage, OrderedSum

SHUFFLES = 5


def test_batches_cover_the_samples_with_distinct_seeds():
    batches = split_samples(spp=10, seed=7, batches=4)
    assert [batch.spp for batch in batches] == [3, 3, 2, 2]
    assert [batch.index for batch in batches] == [0, 1, 2, 3]
    assert batches[0].seed == 7  # one batch is wgputrace.render's own render
    assert len({batch.seed for batch in batches}) == 4
    assert [batch.seed for batch in split_samples(10, 7, 4)] == [batch.seed for batch in batches]
    assert batch_seed(8, 1) != batch_seed(7, 1)


@pytest.mark.parametrize(("spp", "count"), [(3, 3), (DEFAULT_BATCHES, DEFAULT_BATCHES), (1000, DEFAULT_BATCHES)])
def test_the_default_batch_count_depends_on_the_samples_alone(spp, count):
    batches = split_samples(spp, seed=1)
    assert len(batches) == count
    assert sum(batch.spp for batch in batches) == spp


@pytest.mark.parametrize("batches", [0, 11])
def test_batch_counts_beyond_the_samples_are_refused(batches):
    with pytest.raises(ValueError, match=f"batches must be from 1 to spp \\(10\\), got {batches}"):
        split_samples(10, 1, batches)


def _batch_images(rng, count: int) -> list[BatchImage]:
    # means spanning magnitudes, so float rounding depends on the order of the additions
    return [
        BatchImage(index, (rng.random((4, 5, 3)) * 10.0 ** rng.integers(-3, 4)).astype(np.float32), 1 + index % 3)
        for index in range(count)
    ]


def test_the_merge_is_the_same_bits_in_any_order_of_arrival(rng):
    images = _batch_images(rng, 9)
    in_order = OrderedSum()
    for image in images:
        in_order.add(image)
    expected = in_order.image()
    for _ in range(SHUFFLES):
        shuffled = OrderedSum()
        for position in rng.permutation(len(images)):
            shuffled.add(images[position])
        assert shuffled.samples == in_order.samples
        assert np.array_equal(shuffled.image(), expected)
    # the weighted mean of the batch means, as float64 arithmetic in another order gives it
    weights = np.array([image.samples for image in images], np.float64)
    means = np.stack([image.mean.astype(np.float64) for image in images])
    np.testing.assert_allclose(expected, np.tensordot(weights, means, 1) / weights.sum(), rtol=1e-6)


def test_one_batch_merges_to_its_own_mean_bit_for_bit(rng):
    image = _batch_images(rng, 1)[0]
    merged = OrderedSum()
    merged.add(BatchImage(0, image.mean, 7))
    assert np.array_equal(merged.image(), image.mean)


def test_a_batch_merged_twice_is_refused(rng):
    images = _batch_images(rng, 2)
    merged = OrderedSum()
    merged.add(images[1])
    with pytest.raises(ValueError, match="batch 1 was merged already"):
        merged.add(images[1])
    merged.add(images[0])
    with pytest.raises(ValueError, match="batch 0 was merged already"):
        merged.add(images[0])
