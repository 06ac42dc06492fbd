"""The work one Ray actor does: a Renderer built once for the job's scene, then batch after batch
from it; or an animation's frames, each from the scene file's text.

`RenderWorker` is a plain class (`WorkerPool` makes it an actor), so its work can be checked without
Ray. A batch restarts the same Renderer at the batch's seed (`Renderer.restart(seed)`), so the scene, its BVH,
its buffers and its pipelines are built once per worker, not per batch.
"""

from __future__ import annotations

import os
import socket
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..loaders.python_scene import scene_from_source
from ..render import Renderer
from ..scene import Camera, Scene
from .batches import Batch
from .merge import BatchImage
from .tiles import Tile, TileCamera, split_image

# Where a worker renders on the CPU (lavapipe), one thread each: Ray gives every worker a CPU of
# its own, and lavapipe's default of one thread per core would have the workers fight over them.
LAVAPIPE_THREADS = "LP_NUM_THREADS"


@dataclass(frozen=True)
class RenderSettings:
    """What every batch or frame of a job shares: the image, the seed, the path depth, the
    Renderer's other keyword arguments (accel, integrator, ...) and the side of its tiles (None:
    the image is one tile)."""

    width: int
    height: int
    seed: int = 1
    max_depth: int = 9
    options: dict = field(default_factory=dict)
    tile_side: int | None = None

    def tiles(self) -> list[Tile]:
        return split_image(self.width, self.height, self.tile_side)

    def renderer(self, scene: Scene, shape: tuple[int, int] | None = None) -> Renderer:
        """A Renderer of the whole image, or of a tile of `shape` (width, height)."""
        width, height = shape or (self.width, self.height)
        return Renderer(scene, width, height, seed=self.seed, max_depth=self.max_depth, **self.options)


@dataclass(frozen=True)
class WorkerIdentity:
    """Where a worker runs: its process, its host and the adapter it renders on."""

    pid: int
    host: str
    adapter: str

    def __str__(self) -> str:
        return f"worker {self.pid} on {self.host} ({self.adapter})"


@dataclass(frozen=True)
class BatchOutcome:
    """A batch's image and the worker's seconds for it: rendering (dispatches, waits) and reading
    the mean back."""

    image: BatchImage
    render_seconds: float
    readback_seconds: float


@dataclass(frozen=True)
class FrameOutcome:
    """An animation frame's image (float32 (H, W, 3)) and the seconds its worker took: building
    the scene and Renderer, and rendering."""

    frame: int
    image: np.ndarray
    build_seconds: float
    render_seconds: float


class RenderWorker:
    """One worker's renderers (one per tile shape; one in all for an untiled image) and the calls
    the driver makes on it."""

    def __init__(self, on_cpu: bool = False) -> None:
        if on_cpu:
            os.environ[LAVAPIPE_THREADS] = "1"  # read when the device is made, on first use
        self.renderers: dict[tuple[int, int], Renderer] = {}
        self.scene: Scene | None = None
        self.camera: Camera | None = None  # the scene's own, which tiles cut
        self.settings: RenderSettings | None = None

    def identity(self) -> WorkerIdentity:
        from ..gpu.device import gpu

        return WorkerIdentity(os.getpid(), socket.gethostname(), gpu().adapter_name)

    def prepare(self, scene: Scene, settings: RenderSettings) -> float:
        """Build the Renderer the job's batches use (BVH, buffers, pipeline; of the first tile's
        shape where the image is tiled, the others' on first use); its seconds."""
        start = time.perf_counter()
        self.scene, self.camera, self.settings = scene, scene.camera, settings
        self._renderer(settings.tiles()[0])
        return time.perf_counter() - start

    def _renderer(self, tile: Tile) -> Renderer:
        if tile.shape not in self.renderers:
            self.renderers[tile.shape] = self.settings.renderer(self.scene, tile.shape)
        return self.renderers[tile.shape]

    def render_batch(self, batch: Batch, tile: Tile | None = None) -> BatchOutcome:
        """`batch` of the whole image, or of `tile` of it."""
        if self.settings is None:
            raise RuntimeError("render_batch before prepare: the worker has no scene")
        if tile is None:
            tile = self.settings.tiles()[0]
        renderer = self._renderer(tile)
        if self.settings.tile_side is not None:
            renderer.set_camera(TileCamera.of(self.camera, self.settings.width, self.settings.height, tile))
        renderer.restart(tile.seed(batch.seed))
        start = time.perf_counter()
        renderer.render(batch.spp)
        rendered = time.perf_counter()
        mean = renderer.image()
        dropped = renderer.dropped_samples
        image = BatchImage(batch.index, mean, batch.spp, dropped)
        return BatchOutcome(image, rendered - start, time.perf_counter() - rendered)

    def render_frame(self, source: str, path: str, frame: int, spp: int, settings: RenderSettings) -> FrameOutcome:
        """Frame `frame` of the animation whose scene file `path` holds `source`, from scratch."""
        start = time.perf_counter()
        renderer = settings.renderer(scene_from_source(source, Path(path), frame))
        built = time.perf_counter()
        renderer.render(spp)
        image = renderer.image()
        return FrameOutcome(frame, image, built - start, time.perf_counter() - built)
