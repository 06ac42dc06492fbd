"""OrthographicCamera: parallel rays from a rectangle, no perspective (Mitsuba 3's `orthographic`).

| parameter   | type      | default  | meaning                                                            |
|-------------|-----------|----------|--------------------------------------------------------------------|
| position, forward, up | |         | the rectangle's centre, the rays' direction, the image's up        |
| view_height | float > 0 | required | the rectangle's height in scene units; its width follows the image |

A pixel's ray starts at a uniformly jittered point of its part of the rectangle (a box filter) and
runs along forward; nothing behind the rectangle is seen. WGSL: `camera/orthographic.wgsl`.
Mitsuba 3: `orthographic`, its [-1, 1] x [-1 / aspect, 1 / aspect] scaled by half the width.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .sensor import Sensor

# Framed, the rectangle stands this many radii before the sphere's centre: outside the sphere,
# whose points behind the rectangle it would not see.
FRAMING_STANDOFF = 2.0


@dataclass
class OrthographicCamera(Sensor):
    """Parallel rays along `forward` from a rectangle centred on `position`, `view_height` high
    (its width follows the image's aspect), `up` the image's up."""

    view_height: float = field(kw_only=True)

    kind = 3
    shader = "camera/orthographic.wgsl"

    def checked_lens(self) -> dict[str, object]:
        return {"view_height": self.check_length("view_height", self.view_height, zero=False)}

    @classmethod
    def looking_at(cls, position, target, up=(0.0, 1.0, 0.0), *, view_height: float) -> OrthographicCamera:
        """The camera at `position` looking at `target`, `up` the image's up, its rectangle
        `view_height` high."""
        return cls(position, np.subtract(target, position), up, view_height=view_height)

    def half_extents(self, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
        """(right, up): half the rectangle's width and height as vectors, for a `width` x `height` image."""
        right, up, _ = self.basis()
        half_height = self.view_height / 2.0
        return right * half_height * width / height, up * half_height

    def fill_frame(self, record: np.ndarray, width: int, height: int) -> None:
        right, up = self.half_extents(width, height)
        record["camera_position"] = self.position
        record["camera_right"], record["camera_up"], record["camera_forward"] = right, up, self.forward

    def framed(self, radius: float, aspect: float) -> tuple[float, OrthographicCamera]:
        """Outside the sphere, the rectangle as wide and high as it."""
        return FRAMING_STANDOFF * radius, replace(self, view_height=2.0 * radius / min(1.0, aspect))

    def clip_matrix(self, width: int, height: int, near: float, far: float) -> np.ndarray:
        """Clip w = 1: no perspective divide."""
        right, up = self.half_extents(width, height)
        forward = np.asarray(self.forward)
        rows = [
            np.append(right / right.dot(right), 0.0),
            np.append(up / up.dot(up), 0.0),
            np.append(forward / (far - near), -near / (far - near)),
            np.array([0.0, 0.0, 0.0, 1.0]),
        ]
        return self.translated(np.array(rows))

    def mitsuba_sensor(self, width: int, height: int) -> dict:
        half_width = self.view_height / 2.0 * width / height
        return {"type": "orthographic", "to_world": {"look_at": self.look_at(), "scale": (half_width, half_width, 1.0)}}
