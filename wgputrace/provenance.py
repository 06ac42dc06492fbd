"""How an image was made, kept in the image file (`save_image` puts it in PNG text chunks, EXR
header attributes or an .npy's sidecar JSON), and read back by `wgputrace info FILE`.

Every value is a string; each key is written as `wgputrace:<key>`:

| key               | value                                                                   |
|-------------------|-------------------------------------------------------------------------|
| version           | wgputrace's version                                                     |
| scene             | a built-in scene's name, a scene file's name, or `python` for a Scene   |
|                   | built in Python                                                         |
| scene_sha256      | a scene file's bytes hashed (not files it refers to: an .mtl, a .bin);  |
|                   | for `python`, the scene as the GPU got it (triangles and materials      |
|                   | records) and its camera, so equal scenes hash equal; absent for a       |
|                   | built-in scene (the version fixes it)                                   |
| width, height     | image size in pixels                                                    |
| spp               | samples per pixel the image holds (fewer than asked when stopped)       |
| seed              | the Renderer's seed                                                     |
| integrator        | mis, nee, bsdf or bdpt                                                  |
| sampler           | sobol or independent                                                    |
| kernel            | the kernel variant's label (`KernelVariant.label`)                      |
| max_depth         | Mitsuba's max_depth (1: emitters seen directly only); -1 for no limit   |
| accel             | bvh or flat                                                             |
| camera            | the camera's kind and parameters (`Sensor.description`)                 |
| tonemap, exposure | a PNG's tone curve, and its exposure in EV (`auto: +1.25 EV` where      |
|                   | measured from the image); the PNG writer's to add (`tone_metadata`)     |
| adapter, backend  | the GPU adapter's name and its API (Vulkan, Metal, ...)                 |
| render_seconds    | the render time the caller gives; the CLI's: the dispatches' time       |
|                   | (RenderStats.render_seconds), no scene loading or setup                 |
| nonfinite_samples | samples dropped (counted as zero) for being NaN or infinite             |
| cut_short_samples | samples dropped because the driver's loop budget may have cut them      |
| environment       | `none`; a constant's radiance; or a map's source file name and the      |
|                   | sha256 of its texels, with intensity, rotation and visibility          |
| lights            | the light sources besides emissive triangles, by kind (`2 PointLight`)  |
| stopped_by        | SIGINT, SIGTERM or time limit, when the render stopped before its spp   |
| denoised          | oidn, when the image was denoised (`wgputrace render --denoise`)        |
| denoiser_device   | the OIDN device that denoised it (CPU, CUDA)                            |
| date              | when the metadata was made, UTC, ISO 8601                               |
"""

from __future__ import annotations

import hashlib
from collections import Counter
from collections.abc import Mapping, Sequence
from datetime import datetime, timezone
from importlib.metadata import version
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .image_io import AUTO_EXPOSURE, read_text_metadata, sidecar_path
from .loaders.resolve import scene_file
from .scene.cameras import Camera

if TYPE_CHECKING:
    from .render import Renderer
    from .scene.lights import Light
    from .scene.lights.environment import Environment

# One attribute per key rather than one JSON text: exrheader prints each attribute on its own line
# (`wgputrace:spp (type string): "64"`), PIL's `Image.text` and exiftool list each text chunk, so
# every value reads on its own. The prefix keeps our keys apart from other software's (as OIIO's
# `oiio:ColorSpace`, ImageMagick's `png:...`).
NAMESPACE = "wgputrace:"
KEYS = (
    "version",
    "scene",
    "scene_sha256",
    "width",
    "height",
    "spp",
    "seed",
    "integrator",
    "sampler",
    "kernel",
    "max_depth",
    "accel",
    "camera",
    "tonemap",
    "exposure",
    "adapter",
    "backend",
    "render_seconds",
    "nonfinite_samples",
    "cut_short_samples",
    "environment",
    "lights",
    "stopped_by",
    "denoised",
    "denoiser_device",
    "date",
)
PYTHON_SCENE = "python"


def render_metadata(
    renderer: Renderer, scene: str | Path | None, render_seconds: float, *, stopped_by: str | None = None
) -> dict[str, str]:
    """What `renderer` made, for save_image's `metadata`. `scene` is the spec the user gave (a
    built-in name or a file, as load_scene takes it), or None for a Scene built in Python;
    `stopped_by` says what ended the render early (SIGINT, SIGTERM, time limit)."""
    info = renderer.context.adapter.info
    values = {
        "version": version("wgputrace"),
        **_scene_identity(renderer, scene),
        "width": renderer.width,
        "height": renderer.height,
        "spp": renderer.stats.samples_per_pixel,
        "seed": renderer.seed,
        "integrator": renderer.integrator.name,
        "sampler": renderer.sampler,
        "kernel": renderer.variant.label,
        "max_depth": renderer.max_depth,
        "accel": renderer.accel,
        "camera": renderer.scene.camera.description(),
        "adapter": info["device"],
        "backend": info["backend_type"],
        "render_seconds": f"{render_seconds:.3f}",
        "nonfinite_samples": renderer.nonfinite_samples,
        "cut_short_samples": renderer.cut_short_samples,
        "environment": _environment(renderer.scene.environment),
        "lights": _lights(renderer.scene.lights),
        **({"stopped_by": stopped_by} if stopped_by is not None else {}),
        "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    return {NAMESPACE + key: str(value) for key, value in values.items()}


def _scene_identity(renderer: Renderer, scene: str | Path | None) -> dict[str, str]:
    if scene is None:
        return {"scene": PYTHON_SCENE, "scene_sha256": _records_sha256(renderer)}
    path = scene_file(scene)
    if path is None:
        return {"scene": str(scene)}
    return {"scene": path.name, "scene_sha256": hashlib.sha256(path.read_bytes()).hexdigest()}


def _records_sha256(renderer: Renderer) -> str:
    """The scene as rendered: its GPU records as last uploaded (triangles in the BVH's order, which
    a given scene and accel fix) and the camera, which lives in the frame uniform instead: its
    parameters' numbers, and its kind's name unless it is the pinhole (so pinholes hash as they did
    before there were camera kinds)."""
    camera = renderer.scene.camera
    digest = hashlib.sha256()
    digest.update(renderer.records.triangles.tobytes())
    digest.update(renderer.records.materials.tobytes())
    values = [value for name in camera.parameter_names() for value in np.ravel(getattr(camera, name))]
    digest.update(np.array(values, np.float64).tobytes())
    if camera.kind != Camera.kind:
        digest.update(type(camera).__name__.encode())
    return digest.hexdigest()


def tone_metadata(operator: str, requested: float | str, exposure: float) -> dict[str, str]:
    """The keys a PNG adds: its tone curve `operator`, and its `exposure` in EV (`requested`: the
    exposure asked for, "auto" where it was measured from the image)."""
    shown = f"{exposure:+.3g} EV"
    return {
        NAMESPACE + "tonemap": operator,
        NAMESPACE + "exposure": shown if requested != AUTO_EXPOSURE else f"auto: {shown}",
    }


def _environment(environment: Environment | None) -> str:
    if environment is None:
        return "none"
    if environment.texels is None:
        what = "radiance " + ",".join(f"{channel:g}" for channel in environment.radiance)
    else:
        digest = hashlib.sha256(np.ascontiguousarray(environment.texels).tobytes()).hexdigest()
        width, height = environment.size
        what = f"{Path(environment.source).name} {width}x{height} texels sha256 {digest}"
    shown = "" if environment.visible else ", hidden from the camera"
    return f"{what}, intensity {environment.intensity:g}, rotation {environment.rotation_degrees:g} degrees{shown}"


def _lights(lights: Sequence[Light]) -> str:
    kinds = Counter(type(light).__name__ for light in lights)
    return ", ".join(f"{count} {kind}" for kind, count in sorted(kinds.items())) or "none"


def read_metadata(path: str | Path) -> dict[str, str]:
    """The wgputrace metadata of the image file at `path` that save_image wrote, keys in the
    documented order. Raises a one-line ValueError naming the file when it does not exist, cannot be
    read, or holds none."""
    path = Path(path)
    ours = {key: value for key, value in read_text_metadata(path).items() if key.startswith(NAMESPACE)}
    if not ours:
        where = (
            f"no {sidecar_path(path).name} beside it"
            if path.suffix.lower() == ".npy"
            else "written elsewhere, or saved without metadata"
        )
        raise ValueError(f"{path}: has no wgputrace metadata ({where})")
    order = {NAMESPACE + key: index for index, key in enumerate(KEYS)}
    # a stable sort: keys of a later version keep their order after the known ones
    return dict(sorted(ours.items(), key=lambda item: order.get(item[0], len(order))))


def format_metadata(metadata: Mapping[str, str]) -> str:
    """Aligned `key  value` lines (keys without the namespace), as `wgputrace info FILE` prints them."""
    rows = [(key.removeprefix(NAMESPACE), value) for key, value in metadata.items()]
    width = max((len(key) for key, _ in rows), default=0)
    return "\n".join(f"{key:<{width}}  {value}" for key, value in rows)


__all__ = ["KEYS", "NAMESPACE", "format_metadata", "read_metadata", "render_metadata", "tone_metadata"]
