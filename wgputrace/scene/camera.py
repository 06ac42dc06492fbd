"""Pinhole camera: position, look direction (or target), up, vertical field of view.

Right-handed: image right = cross(forward, up), image up = cross(right, forward); row 0 of an
image is its top. The sample position inside a pixel is uniform (a box filter).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SceneError

# Below this |cross(forward, up)| the up vector gives no usable "right" direction.
_PARALLEL_LIMIT = 1e-6


@dataclass
class Camera:
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    forward: tuple[float, float, float] = (0.0, 0.0, 1.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    vfov_degrees: float = 60.0

    def __post_init__(self) -> None:
        position, forward, up = (
            _vector(label, v) for label, v in (("position", self.position), ("forward", self.forward), ("up", self.up))
        )
        try:
            vfov = float(self.vfov_degrees)
        except (TypeError, ValueError):
            vfov = math.nan
        if not 0.0 < vfov < 180.0:
            raise SceneError(f"camera vfov_degrees must be in (0, 180), got {self.vfov_degrees!r}")
        if np.linalg.norm(forward) == 0.0:
            raise SceneError("camera forward is the zero vector")
        if not np.isfinite(np.linalg.norm(forward)):
            raise SceneError(f"camera forward {forward.tolist()} is too long to normalize")
        forward = forward / np.linalg.norm(forward)
        if np.linalg.norm(np.cross(forward, up)) < _PARALLEL_LIMIT * max(np.linalg.norm(up), 1.0):
            raise SceneError(f"camera up {up.tolist()} is parallel to forward {forward.tolist()}")
        self.position = tuple(position.tolist())
        self.forward = tuple(forward.tolist())
        self.up = tuple(up.tolist())
        self.vfov_degrees = vfov

    @classmethod
    def looking_at(cls, position, target, up=(0.0, 1.0, 0.0), vfov_degrees: float = 60.0) -> Camera:
        return cls(position, np.subtract(target, position), up, vfov_degrees)

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit (right, up, forward) of the image plane."""
        forward = np.asarray(self.forward)
        right = np.cross(forward, self.up)
        right /= np.linalg.norm(right)
        return right, np.cross(right, forward), forward

    def image_plane(self, width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, forward) scaled so that forward + x * right + y * up, x and y in [-1, 1],
        spans the image: the half-extents of the image plane at distance 1."""
        right, up, forward = self.basis()
        half_height = np.tan(np.radians(self.vfov_degrees) / 2.0)
        return right * half_height * width / height, up * half_height, forward


def _vector(label: str, value) -> np.ndarray:
    try:
        vector = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise SceneError(f"camera {label} must be 3 finite numbers, got {value!r}") from None
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise SceneError(f"camera {label} must be 3 finite numbers, got {vector.tolist()}")
    return vector
