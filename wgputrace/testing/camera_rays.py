"""Float64 numpy camera rays of every camera kind, made from the FRAME record the kind writes
(`Sensor.fill_frame`, rounded to float32 as the GPU reads it): the oracle the shipped `camera_ray`
is tested against, and the rays the closed-form camera tests reason with. The equirectangular
camera's directions come from the environment map's own convention (`local_of_uv`), which is the
promise that ties the two together.
"""

from __future__ import annotations

import math

import numpy as np

from wgputrace.gpu.layout import FRAME
from wgputrace.scene.cameras import Camera, EquirectangularCamera, OrthographicCamera, Sensor, ThinLensCamera
from wgputrace.scene.lights.environment import local_of_uv


def frame_of(camera: Sensor, width: int, height: int) -> np.ndarray:
    """The FRAME record `camera` writes for a `width` x `height` image (width and height set)."""
    record = FRAME.zeros(1)
    camera.fill_frame(record, width, height)
    record["width"], record["height"] = width, height
    return record


def concentric_disk(u: np.ndarray) -> np.ndarray:
    """WGSL `sample_concentric_disk`: (n, 2) numbers in [0, 1)^2 -> points of the unit disk."""
    offset = 2.0 * np.asarray(u, np.float64) - 1.0
    x, y = offset[:, 0], offset[:, 1]
    wide = np.abs(x) > np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = np.where(wide, x, y)
        phi = np.where(wide, 0.25 * math.pi * (y / x), 0.5 * math.pi - 0.25 * math.pi * (x / y))
    disk = radius[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    disk[(x == 0.0) & (y == 0.0)] = 0.0
    return disk


def camera_rays(
    camera: Sensor, width: int, height: int, pixels: np.ndarray, jitter: np.ndarray, lens: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(origins, unit directions), (n, 3) each: the rays through point `jitter` (n, 2) of `pixels`
    (n, 2: column, row; row 0 on top) from lens samples `lens` (n, 2), as WGSL `camera_ray` makes them."""
    frame = {name: np.asarray(frame_of(camera, width, height)[name][0], np.float64) for name in FRAME.dtype.names}
    point = np.asarray(pixels, np.float64) + np.asarray(jitter, np.float64)
    ndc = point / (width, height) * 2.0 - 1.0
    position, right, up, forward = (frame[f"camera_{name}"] for name in ("position", "right", "up", "forward"))
    if type(camera) is EquirectangularCamera:
        local = local_of_uv(point / (width, height))
        # the map's frame: +x is the image's left (u grows towards -x at the centre), +z its centre
        directions = -local[:, :1] * right + local[:, 1:2] * up + local[:, 2:] * forward
        return np.broadcast_to(position, directions.shape).copy(), directions
    if type(camera) is OrthographicCamera:
        origins = position + ndc[:, :1] * right - ndc[:, 1:] * up
        return origins, np.broadcast_to(forward, origins.shape).copy()
    through = forward + ndc[:, :1] * right - ndc[:, 1:] * up
    if type(camera) is Camera:
        return np.broadcast_to(position, through.shape).copy(), _unit(through)
    if type(camera) is ThinLensCamera:
        disk = concentric_disk(lens) * frame["aperture_radius"]
        origins = position + disk[:, :1] * _unit(right) + disk[:, 1:] * _unit(up)
        return origins, _unit(position + frame["focus_distance"] * through - origins)
    raise TypeError(f"no ray oracle for {type(camera).__name__}")


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)
