"""A worker's batches, without Ray: each is the image a fresh Renderer seeded with the batch's seed
makes, from one Renderer built once; a render in one batch is wgputrace.render's."""

from __future__ import annotations

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.cluster.batches import split_samples
from wgputrace.cluster.merge import OrderedSum
from wgputrace.cluster.worker import RenderSettings, RenderWorker
from wgputrace.kernels.sampler import SAMPLERS

pytestmark = pytest.mark.gpu

SIZE = 16
SEED = 5


@pytest.fixture(scope="module")
def worker():
    worker = RenderWorker()
    worker.prepare(wt.default_scene(), RenderSettings(SIZE, SIZE, SEED))
    return worker


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_every_batch_is_a_fresh_renderer_at_its_seed(sampler):
    scene = wt.default_scene()
    worker = RenderWorker()
    worker.prepare(scene, RenderSettings(SIZE, SIZE, SEED, options={"sampler": sampler}))
    # in reverse: what a batch gives must not depend on the batches the worker rendered before it
    for batch in reversed(split_samples(6, SEED, 3)):
        outcome = worker.render_batch(batch)
        expected = wt.render(scene, spp=batch.spp, width=SIZE, height=SIZE, seed=batch.seed, sampler=sampler)
        assert outcome.image.samples == batch.spp
        assert np.array_equal(outcome.image.mean, expected), f"batch {batch.index}"


def test_one_batch_is_wgputrace_render(worker):
    merged = OrderedSum()
    for batch in split_samples(4, SEED, 1):
        merged.add(worker.render_batch(batch).image)
    assert np.array_equal(merged.image(), wt.render(wt.default_scene(), spp=4, width=SIZE, height=SIZE, seed=SEED))


def test_a_worker_without_a_scene_says_so():
    with pytest.raises(RuntimeError, match="before prepare"):
        RenderWorker().render_batch(split_samples(1, 1)[0])
