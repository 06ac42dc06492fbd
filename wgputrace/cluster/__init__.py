"""Rendering on a Ray cluster: one image's samples in batches across GPU (or CPU) workers, merged
exactly; an animation's frames, one task per frame, resumable. Needs the `ray` extra
(`pip install "wgputrace[ray]"`); importing this package does not import Ray, and every call
without it raises RayMissing saying how to install it.

    import wgputrace as wt
    img = wt.cluster.render(scene, spp=1024, width=512, height=512, seed=1, address="auto")

The image is the same, bit for bit, for any number of workers and any order in which they finish
(`split_samples`, `OrderedSum`), and converges to wgputrace.render's picture; a worker lost
mid-render has its batches run again elsewhere with the same result (`WorkerPool`).
"""

from .batch_render import BatchTiming, ClusterRender, render, render_batches
from .batches import DEFAULT_BATCHES, Batch, batch_seed, split_samples
from .connection import AUTO, CONNECT_TIMEOUT_SECONDS
from .errors import INSTALL_HINT, ClusterUnreachable, NoWorkersLeft, RayMissing, WorkerFailed
from .frames import FramesReport, frame_path, parse_frames, render_frames
from .progress import ClusterProgress

__all__ = [
    "AUTO",
    "CONNECT_TIMEOUT_SECONDS",
    "DEFAULT_BATCHES",
    "INSTALL_HINT",
    "Batch",
    "BatchTiming",
    "ClusterProgress",
    "ClusterRender",
    "ClusterUnreachable",
    "FramesReport",
    "NoWorkersLeft",
    "RayMissing",
    "WorkerFailed",
    "batch_seed",
    "frame_path",
    "parse_frames",
    "render",
    "render_batches",
    "render_frames",
    "split_samples",
]
