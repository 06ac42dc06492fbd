"""Camera: the pinhole (Mitsuba 3's `perspective`).

| parameter    | type      | default   | meaning                                               |
|--------------|-----------|-----------|-------------------------------------------------------|
| position     | 3 numbers | (0, 0, 0) | the pinhole                                           |
| forward      | 3 numbers | (0, 0, 1) | the viewing direction (normalised)                    |
| up           | 3 numbers | (0, 1, 0) | the image's up; not parallel to forward              |
| vfov_degrees | float     | 60        | the vertical field of view, in (0, 180)               |

Rays leave the pinhole through a uniformly jittered point of the pixel (a box filter); the
horizontal field of view follows the image's aspect ratio. WGSL: `camera/perspective.wgsl`, which
draws no lens sample. Mitsuba 3: `perspective` with fov_axis y.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .sensor import Sensor


@dataclass
class Camera(Sensor):
    """The pinhole camera at `position` looking along `forward`, `up` the image's up, seeing
    `vfov_degrees` from the image's bottom to its top (the module's table gives the ranges)."""

    vfov_degrees: float = 60.0

    kind = 1
    shader = "camera/perspective.wgsl"

    def checked_lens(self) -> dict[str, object]:
        try:
            vfov = float(self.vfov_degrees)
        except (TypeError, ValueError):
            vfov = math.nan
        if not 0.0 < vfov < 180.0:
            raise self.parameter_error(
                f"{self.label}: vfov_degrees must be in (0, 180), got {self.vfov_degrees!r}", "vfov_degrees"
            )
        return {"vfov_degrees": vfov}

    @classmethod
    def looking_at(cls, position, target, up=(0.0, 1.0, 0.0), vfov_degrees: float = 60.0, **lens) -> Camera:
        """The camera at `position` looking at `target`, `up` the image's up and `vfov_degrees` its
        vertical field of view; `lens`: the kind's further parameters."""
        return cls(position, np.subtract(target, position), up, vfov_degrees, **lens)

    def image_plane(self, width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, forward) scaled so that forward + x * right + y * up, x and y in [-1, 1],
        spans the image: the half-extents of the image plane at distance 1."""
        right, up, forward = self.basis()
        half_height = np.tan(np.radians(self.vfov_degrees) / 2.0)
        return right * half_height * width / height, up * half_height, forward

    def fill_frame(self, record: np.ndarray, width: int, height: int) -> None:
        right, up, forward = self.image_plane(width, height)
        record["camera_position"] = self.position
        record["camera_right"], record["camera_up"], record["camera_forward"] = right, up, forward

    def framed(self, radius: float, aspect: float) -> tuple[float, Camera]:
        """Where the sphere just fills the narrower field of view."""
        half_vertical = math.radians(self.vfov_degrees) / 2
        half_horizontal = math.atan(math.tan(half_vertical) * aspect)
        return radius / math.sin(min(half_vertical, half_horizontal)), self

    def clip_matrix(self, width: int, height: int, near: float, far: float) -> np.ndarray:
        """Clip w = the distance along forward (a perspective divide)."""
        right, up, forward = self.image_plane(width, height)
        depth_scale = far / (far - near)
        rows = [
            np.append(right / right.dot(right), 0.0),
            np.append(up / up.dot(up), 0.0),
            np.append(forward * depth_scale, -near * depth_scale),
            np.append(forward, 0.0),
        ]
        return self.translated(np.array(rows))

    def mitsuba_sensor(self, width: int, height: int) -> dict:
        return {
            "type": "perspective",
            "fov_axis": "y",
            "fov": self.vfov_degrees,
            "to_world": {"look_at": self.look_at()},
        }
