"""An animation rendered in order on one renderer (`wgputrace render-frames --temporal`): a .py
scene file defining scene(frame), each frame a `Renderer.render_frame`, so every pixel keeps its
samples from frame to frame (docs/guide/frames_in_motion.md) instead of each frame starting again.

scene(frame) builds a new Scene each frame; `follow_frame` carries what changed into the renderer's
scene and keeps what did not (the same shapes, materials, lights and environment), so a frame that
changes nothing adds its samples as a resting camera does, and a shape that only moved is refitted
rather than rebuilt.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .cluster.frames import frame_path
from .image_io import DEFAULT_TONEMAP, save_image
from .loaders.python_scene import read_source, scene_from_source
from .render import Renderer
from .scene import Scene

# How deep `_alike` compares nested values (a material's texture's image, an environment's map).
ALIKE_DEPTH = 4


@dataclass
class TemporalFrame:
    """One frame rendered: its number, the file written, its samples per pixel and tracing time."""

    frame: int
    path: Path
    samples_per_pixel: int
    seconds: float


def _alike(a, b, depth: int = ALIKE_DEPTH) -> bool:
    """Whether two values of scene(frame)'s making hold the same data: arrays equal, objects of one
    type with alike attributes (dataclass fields or instance variables), lists and tuples alike
    element by element."""
    if a is b:
        return True
    if type(a) is not type(b):
        return False
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b)
    if isinstance(a, list | tuple):
        return len(a) == len(b) and all(_alike(x, y, depth) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_alike(a[key], b[key], depth) for key in a)
    if isinstance(a, str | bytes | int | float | bool | complex | Path) or a is None:
        return a == b
    if depth == 0:
        return False
    fields = vars(a) if hasattr(a, "__dict__") else {f.name: getattr(a, f.name) for f in dataclasses.fields(a)}
    other = vars(b) if hasattr(b, "__dict__") else {f.name: getattr(b, f.name) for f in dataclasses.fields(b)}
    return _alike(fields, other, depth - 1)


def _geometry(shape) -> dict:
    """A shape's data but its placement, material and edit counters."""
    skipped = ("_transform", "_material", "_world", "_world_normals")
    return {key: value for key, value in vars(shape).items() if key not in skipped and not key.endswith("_version")}


def follow_frame(scene: Scene, following: Scene) -> None:
    """Make `scene` (a renderer's) what `following` (the next frame's scene) shows: its camera; each
    shape of the same name and geometry kept, given the next frame's transform where that moved and
    its material where that changed; everything else as the next frame has it."""
    scene.camera = following.camera
    shapes = []
    for index, shape in enumerate(following.shapes):
        kept = scene.shapes[index] if index < len(scene.shapes) else None
        if kept is None or kept.name != shape.name or not _alike(_geometry(kept), _geometry(shape)):
            shapes.append(shape)
            continue
        if not np.array_equal(kept.transform, shape.transform):
            kept.transform = shape.transform
        if not _alike(kept.material, shape.material):
            kept.material = shape.material
        shapes.append(kept)
    if any(a is not b for a, b in zip(shapes, scene.shapes, strict=False)) or len(shapes) != len(scene.shapes):
        scene.shapes = shapes
    if not _alike(scene.environment, following.environment):
        scene.environment = following.environment
    if not _alike(scene.instances, following.instances):
        scene.instances = following.instances
    if not _alike(scene.lights, following.lights):
        scene.remove_light(*scene.lights)
        scene.add_light(*following.lights)


def render_temporal_frames(
    scene_file: str | Path,
    frames: range,
    output: str,
    width: int = 512,
    height: int = 512,
    *,
    spp: int | None = None,
    budget: float | None = None,
    filtered: bool = False,
    upscale: int = 1,
    exposure: float | str = 0.0,
    tonemap: str = DEFAULT_TONEMAP,
    progress: Callable[[TemporalFrame], None] | None = None,
    **options,
) -> list[TemporalFrame]:
    """Render `frames` of the animation `scene_file` (scene(frame)) in order, each a render_frame of
    `spp` samples per pixel or of `budget` seconds (as render_frame takes them), to `output` (a
    pattern with {frame}); `filtered`: the variance-guided filter's picture; `upscale`: trace one
    pixel of every upscale x upscale block a frame (temporal upsampling). Every frame is written,
    those whose file exists too: the history needs them all. `progress(frame)` is called after each
    file is written. `options`: the Renderer's keyword arguments (seed, max_depth, ...)."""
    path = Path(scene_file)
    source = read_source(path)
    renderer: Renderer | None = None
    done = []
    for frame in frames:
        scene = scene_from_source(source, path, frame)
        if renderer is None:
            renderer = Renderer(scene, width, height, **options)
        else:
            follow_frame(renderer.scene, scene)
        start = time.perf_counter()
        image = renderer.render_frame(spp=spp, budget=budget, filtered=filtered, upscale=upscale)
        seconds = time.perf_counter() - start
        written = save_image(frame_path(output, frame), image, exposure=exposure, tonemap=tonemap)
        done.append(TemporalFrame(frame, written, renderer.stats.samples_per_pixel, seconds))
        if progress is not None:
            progress(done[-1])
    return done
