"""EquirectangularCamera: every direction around a point in one 2:1 image, in the convention of our
environment maps (`Environment`, Mitsuba 3's `envmap`); pbrt-v4's spherical camera with its
equirectangular mapping.

| parameter | type      | default   | meaning                                                     |
|-----------|-----------|-----------|-------------------------------------------------------------|
| position  | 3 numbers | (0, 0, 0) | the centre of the sphere of directions                      |
| forward   | 3 numbers | (0, 0, 1) | what the image's centre sees                                |
| up        | 3 numbers | (0, 1, 0) | what its top row sees                                       |

The point (x, y) of a W x H image, row 0 on top, sees the direction at theta = pi y / H from up and
phi = 2 pi (x / W - 1/2) from forward towards right: sin(theta) sin(phi) right + cos(theta) up +
sin(theta) cos(phi) forward. Looking along +z with +y up that is an environment map's own frame
(u = x / W, v = y / H), so a render of a scene lit by a map alone is the map, resampled (Mitsuba
puts a map's row j at v = j / (H - 1), a pixel's centre is at (j + 1/2) / H). An image that is
not 2:1 is rendered with its pixels stretched, and a CameraWarning says so. WGSL:
`camera/equirectangular.wgsl`. Mitsuba 3 has no such sensor.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .sensor import CameraWarning, Sensor


@dataclass
class EquirectangularCamera(Sensor):
    """Every direction around `position` in one 2:1 image, `forward` at its centre and `up` at its
    top row."""

    kind = 4
    shader = "camera/equirectangular.wgsl"

    def fill_frame(self, record: np.ndarray, width: int, height: int) -> None:
        right, up, forward = self.basis()
        record["camera_position"] = self.position
        record["camera_right"], record["camera_up"], record["camera_forward"] = right, up, forward

    def check_image(self, width: int, height: int) -> None:
        if width != 2 * height:
            warnings.warn(
                f"{self.label}: a {width}x{height} image is not 2:1 ({2 * height}x{height} would be), so its pixels "
                "cover unequal angles across and down",
                CameraWarning,
                stacklevel=3,
            )

    def framed(self, radius: float, aspect: float) -> tuple[float, EquirectangularCamera]:
        """At the centre: every direction is in view."""
        return 0.0, self

    def clip_matrix(self, width: int, height: int, near: float, far: float) -> None:
        """None: no matrix maps the sphere of directions onto a rectangle."""
        return None

    def mitsuba_sensor(self, width: int, height: int) -> None:
        return None
