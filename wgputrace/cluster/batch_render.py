"""One image rendered across a Ray cluster: its samples cut into batches (`split_samples`), the image
into tiles where it is larger than a device allows (`split_image`), each batch of each tile
rendered by whichever worker is free (`WorkerPool`), and the batch images merged per tile in batch
order in float64 (`TiledSum`). The image is the same, bit for bit, for any number of workers and
any order of completion, and a render in one batch is `wgputrace.render`'s image.

The scene goes into Ray's object store once (ray.put); every worker reads it from there and builds
its Renderer once, then renders batch after batch with it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..integrators import integrator, integrator_names
from ..scene import Scene
from .batches import Batch, split_samples
from .connection import connected
from .merge import TiledSum
from .pool import Placement, WorkerPool
from .progress import ClusterProgress
from .tiles import Tile, check_tileable
from .worker import BatchOutcome, RenderSettings, WorkerIdentity


@dataclass(frozen=True)
class BatchTiming:
    """Seconds spent on one batch (of one tile): the worker's rendering and read-back, the driver's merge."""

    index: int
    tile: int
    spp: int
    render_seconds: float
    readback_seconds: float
    merge_seconds: float


@dataclass
class ClusterRender:
    """A finished cluster render: the `image` (float32 (H, W, 3), as wgputrace.render returns it) and
    what it took: the `batches` and `tiles` rendered, the `workers` that rendered one (in the order
    of their first), each worker's Renderer `build_seconds`, the `wall_seconds` of the whole, the
    `lost_workers` and `resubmitted_batches` (run again elsewhere), the `dropped_samples`
    (non-finite or cut short) and the `timings` of every batch."""

    image: np.ndarray
    batches: list[Batch]
    tiles: list[Tile]
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
    tile: int | None = None,
    progress: Callable[[ClusterProgress], None] | None = None,
    **options,
) -> ClusterRender:
    """Render `scene` on the Ray cluster at `address` (connection.connected says which) in
    `batches` batches (None: batches.DEFAULT_BATCHES, at most one per sample) on at most `workers` workers (None: one
    per GPU the cluster has, else one per CPU); `tile`: the side of the square tiles the image is
    cut into, for an image larger than a worker's device allows (its DeviceLimitError names the
    largest square it can render). `options` are the Renderer's other keyword arguments (accel,
    integrator). `progress` is called after every batch (of a tile) merged."""
    method = integrator(options.get("integrator", "mis"))
    if tile is not None and method.splats:
        tiled = ", ".join(name for name in integrator_names() if not integrator(name).splats)
        raise ValueError(
            f"tiles need an integrator that does not splat ({tiled}): {method.name} splats light paths onto the whole image"
        )
    if tile is not None:
        check_tileable(scene.camera)
    work = split_samples(spp, seed, batches)
    settings = RenderSettings(width, height, seed, max_depth, options, tile)
    tiles = settings.tiles()
    tasks = [(batch, piece) for batch in work for piece in tiles]
    with connected(address) as ray:
        start = time.perf_counter()
        scene_ref = ray.put(scene)
        pool = WorkerPool(
            ray, Placement.for_cluster(ray, workers), lambda actor: actor.prepare.remote(scene_ref, settings)
        )
        merged, timings, contributors = TiledSum(width, height, tiles), [], {}
        samples = 0
        try:
            results = pool.run(tasks, lambda actor, task: actor.render_batch.remote(*task))
            for (batch, piece), outcome, worker in results:
                timings.append(_merge(merged, batch, piece, outcome))
                contributors.setdefault(worker, None)
                samples += batch.spp * piece.width * piece.height
                if progress is not None:
                    elapsed = time.perf_counter() - start
                    progress(ClusterProgress(len(timings), len(tasks), samples, elapsed, pool.live, worker))
            return ClusterRender(
                merged.image(),
                work,
                tiles,
                list(contributors),
                pool.setups(),
                time.perf_counter() - start,
                pool.lost,
                pool.resubmitted,
                merged.dropped,
                sorted(timings, key=lambda timing: (timing.index, timing.tile)),
            )
        finally:
            pool.close()


def _merge(merged: TiledSum, batch: Batch, tile: Tile, outcome: BatchOutcome) -> BatchTiming:
    start = time.perf_counter()
    merged.add(tile, outcome.image)
    seconds = time.perf_counter() - start
    return BatchTiming(batch.index, tile.index, batch.spp, outcome.render_seconds, outcome.readback_seconds, seconds)


def render(scene: Scene, spp: int = 64, width: int = 512, height: int = 512, **options) -> np.ndarray:
    """What `wgputrace.render(scene, spp, width, height)` returns (the mean of `spp` samples per
    pixel, float32 (height, width, 3)), rendered on a Ray cluster; `options` are render_batches'
    keyword arguments (seed, max_depth, address, batches, workers, tile, and the Renderer's accel,
    integrator, ...). RayMissing without the ray extra, ClusterUnreachable, NoWorkersLeft and
    WorkerFailed as their names say."""
    return render_batches(scene, spp, width, height, **options).image
