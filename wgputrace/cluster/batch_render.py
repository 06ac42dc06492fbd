"""One image rendered across a Ray cluster: its samples cut into batches (batches.py), each batch
rendered by whichever worker is free (pool.py), the batch images merged in batch order in float64
(merge.py). The image is the same, bit for bit, for any number of workers and any order of
completion, and a render in one batch is `wgputrace.render`'s image.

The scene goes into Ray's object store once (ray.put); every worker reads it from there and builds
its Renderer once, then renders batch after batch with it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..scene import Scene
from .batches import Batch, split_samples
from .connection import connected
from .merge import OrderedSum
from .pool import Placement, WorkerPool
from .progress import ClusterProgress
from .worker import BatchOutcome, RenderSettings, WorkerIdentity


@dataclass(frozen=True)
class BatchTiming:
    """Seconds spent on one batch: the worker's rendering and read-back, the driver's merge."""

    index: int
    spp: int
    render_seconds: float
    readback_seconds: float
    merge_seconds: float


@dataclass
class ClusterRender:
    """A finished cluster render: the image (float32 (H, W, 3), as wgputrace.render returns it) and
    what it took."""

    image: np.ndarray
    batches: list[Batch]
    workers: list[WorkerIdentity]  # those that rendered a batch, in the order of their first
    build_seconds: list[float]  # each worker's Renderer build (BVH, buffers, pipeline)
    wall_seconds: float
    lost_workers: int
    resubmitted_batches: int
    dropped_samples: int
    timings: list[BatchTiming] = field(default_factory=list)


def render_batches(
    scene: Scene,
    spp: int = 64,
    width: int = 512,
    height: int = 512,
    *,
    seed: int = 1,
    max_depth: int = 9,
    address: str | None = None,
    batches: int | None = None,
    workers: int | None = None,
    progress: Callable[[ClusterProgress], None] | None = None,
    **options,
) -> ClusterRender:
    """Render `scene` on the Ray cluster at `address` (connection.connected says which) in
    `batches` batches (None: batches.default_batch_count) on at most `workers` workers (None: one
    per GPU the cluster has, else one per CPU). `options` are the Renderer's other keyword
    arguments (accel, integrator). `progress` is called after every batch merged."""
    work = split_samples(spp, seed, batches)
    settings = RenderSettings(width, height, seed, max_depth, options)
    with connected(address) as ray:
        start = time.perf_counter()
        scene_ref = ray.put(scene)
        pool = WorkerPool(
            ray, Placement.for_cluster(ray, workers), lambda actor: actor.prepare.remote(scene_ref, settings)
        )
        merged, timings, contributors = OrderedSum(), [], {}
        try:
            results = pool.run(work, lambda actor, batch: actor.render_batch.remote(batch))
            for batch, outcome, worker in results:
                timings.append(_merge(merged, batch, outcome))
                contributors.setdefault(worker, None)
                if progress is not None:
                    samples = sum(timing.spp for timing in timings) * width * height
                    elapsed = time.perf_counter() - start
                    progress(ClusterProgress(len(timings), len(work), samples, elapsed, pool.live, worker))
            return ClusterRender(
                merged.image(),
                work,
                list(contributors),
                pool.setups(),
                time.perf_counter() - start,
                pool.lost,
                pool.resubmitted,
                merged.dropped,
                sorted(timings, key=lambda timing: timing.index),
            )
        finally:
            pool.close()


def _merge(merged: OrderedSum, batch: Batch, outcome: BatchOutcome) -> BatchTiming:
    start = time.perf_counter()
    merged.add(outcome.image)
    seconds = time.perf_counter() - start
    return BatchTiming(batch.index, batch.spp, outcome.render_seconds, outcome.readback_seconds, seconds)


def render(
    scene: Scene,
    spp: int = 64,
    width: int = 512,
    height: int = 512,
    *,
    seed: int = 1,
    max_depth: int = 9,
    address: str | None = None,
    batches: int | None = None,
    workers: int | None = None,
    **options,
) -> np.ndarray:
    """What `wgputrace.render` returns (the mean of `spp` samples per pixel, float32 (H, W, 3)),
    rendered on a Ray cluster; the arguments are render_batches'."""
    return render_batches(
        scene,
        spp,
        width,
        height,
        seed=seed,
        max_depth=max_depth,
        address=address,
        batches=batches,
        workers=workers,
        **options,
    ).image
