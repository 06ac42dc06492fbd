"""An animation rendered across a Ray cluster: a .py scene file defining scene(frame), one task per
frame, each frame's image written by the driver as it arrives.

Every file is written atomically (save_image writes a temporary file beside it and renames it), and
a frame whose file exists is not rendered again: a job stopped by Ctrl-C, or by a lost driver,
keeps the frames it finished, and the same command resumes it. The workers build each frame's scene
from the file's text, which the driver reads once and sends through Ray's object store, so the
workers need neither the file nor a shared filesystem.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..image_io import DEFAULT_TONEMAP, save_image
from ..loaders.python_scene import read_source
from .connection import connected
from .pool import Placement, WorkerPool
from .progress import ClusterProgress
from .worker import RenderSettings

FRAME_FIELD = "frame"


@dataclass
class FramesReport:
    """What a frames job did: the files `written` and those `skipped` (found written already),
    and the `lost_workers` whose frames ran again elsewhere."""

    written: list[Path] = field(default_factory=list)
    skipped: list[Path] = field(default_factory=list)
    lost_workers: int = 0


def parse_frames(text: str) -> range:
    """ "START:STOP" (STOP excluded, as Python slices), "START:STOP:STEP" or one frame "N"."""
    try:
        numbers = [int(part) for part in text.split(":")]
    except ValueError:
        raise ValueError(f"frames must look like 0:240, 0:240:2 or 7, got {text!r}") from None
    if len(numbers) == 1:
        numbers.append(numbers[0] + 1)
    if len(numbers) > 3 or numbers[0] < 0 or (len(numbers) == 3 and numbers[2] < 1):
        raise ValueError(f"frames must be START:STOP[:STEP] with START >= 0 and STEP >= 1, got {text!r}")
    frames = range(*numbers)
    if not frames:
        raise ValueError(f"frames {text!r} hold no frame")
    return frames


def frame_path(pattern: str, frame: int) -> Path:
    """The file of `frame`: `pattern` with {frame} (or a format such as {frame:04d}) filled in."""
    try:
        named = pattern.format(**{FRAME_FIELD: frame})
    except (KeyError, IndexError, ValueError) as error:
        raise ValueError(
            f"output {pattern!r}: use {{{FRAME_FIELD}}} or {{{FRAME_FIELD}:04d}} for the frame ({error})"
        ) from None
    if named == pattern:
        raise ValueError(f"output {pattern!r} has no {{{FRAME_FIELD}}}: every frame would write the same file")
    return Path(named)


def render_frames(
    scene_file: str | Path,
    frames: range,
    output: str,
    spp: int = 64,
    width: int = 512,
    height: int = 512,
    *,
    seed: int = 1,
    max_depth: int = 9,
    exposure: float | str = 0.0,
    tonemap: str = DEFAULT_TONEMAP,
    address: str | None = None,
    workers: int | None = None,
    progress: Callable[[ClusterProgress], None] | None = None,
    **options,
) -> FramesReport:
    """Render `frames` of the animation `scene_file` (scene(frame)) to `output` (a pattern with
    {frame}), skipping frames whose file exists; every frame from `seed`, as `wgputrace render` of
    that frame would. `spp`, `width`, `height`, `max_depth`, `address`, `workers`, `progress` and
    the Renderer's `options` are as render_batches takes them; `tonemap` and `exposure` (EV, or
    "auto" per frame) as save_image takes them."""
    path = Path(scene_file)
    source = read_source(path)
    report = FramesReport()
    todo = []
    for frame in frames:
        target = frame_path(output, frame)
        if target.exists():
            report.skipped.append(target)
        else:
            todo.append(frame)
    if not todo:
        return report
    settings = RenderSettings(width, height, seed, max_depth, options)
    with connected(address) as ray:
        start = time.perf_counter()
        source_ref = ray.put(source)
        pool = WorkerPool(ray, Placement.for_cluster(ray, workers), lambda actor: actor.identity.remote())

        def submit(actor, frame: int):
            return actor.render_frame.remote(source_ref, str(path), frame, spp, settings)

        try:
            for frame, outcome, worker in pool.run(todo, submit):
                written = save_image(frame_path(output, frame), outcome.image, exposure=exposure, tonemap=tonemap)
                report.written.append(written)
                if progress is not None:
                    done = len(report.written)
                    elapsed = time.perf_counter() - start
                    progress(ClusterProgress(done, len(todo), done * spp * width * height, elapsed, pool.live, worker))
        finally:
            report.lost_workers = pool.lost
            pool.close()
    return report
