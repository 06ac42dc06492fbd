"""ThinLensCamera: a perspective camera whose lens has an aperture, so that only the plane at
`focus_distance` is sharp (Mitsuba 3's `thinlens`).

| parameter       | type       | default   | meaning                                                   |
|-----------------|------------|-----------|-----------------------------------------------------------|
| position, forward, up, vfov_degrees | | | as Camera's; position is the lens's centre              |
| aperture_radius | float >= 0 | required  | the lens's radius in scene units (0: a pinhole's picture)  |
| focus_distance  | float > 0  | required  | from the lens to the plane in focus, along forward        |

A ray leaves a point uniform on the lens disc (the sampler's 2D draw after the pixel's) towards
where the pinhole's ray through the same pixel point meets the plane in focus. A point at distance
d along forward is imaged as a disc of radius aperture_radius |1 / focus_distance - 1 / d| on the
image plane at distance 1 (the pixels: that times height / (2 tan(vfov / 2))). A photographer's
f-number N and focal length f give aperture_radius = f / (2 N), in the scene's units. WGSL:
`camera/thin_lens.wgsl`. Mitsuba 3: `thinlens` with fov_axis y.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .perspective import Camera


@dataclass
class ThinLensCamera(Camera):
    """A camera at `position` looking along `forward` (`up` the image's up, `vfov_degrees` its
    vertical field of view) through a lens of `aperture_radius`, sharp at `focus_distance` along
    `forward` (the module's table gives the ranges)."""

    aperture_radius: float = field(kw_only=True)
    focus_distance: float = field(kw_only=True)

    kind = 2
    shader = "camera/thin_lens.wgsl"

    def checked_lens(self) -> dict[str, object]:
        checked = super().checked_lens()
        checked["aperture_radius"] = self.check_length("aperture_radius", self.aperture_radius, zero=True)
        checked["focus_distance"] = self.check_length("focus_distance", self.focus_distance, zero=False)
        return checked

    @classmethod
    def looking_at(
        cls,
        position,
        target,
        up=(0.0, 1.0, 0.0),
        vfov_degrees: float = 60.0,
        *,
        aperture_radius: float,
        focus_distance: float | None = None,
    ) -> ThinLensCamera:
        """The camera at `position` looking at `target` (`up` the image's up, `vfov_degrees` its
        vertical field of view) through a lens of `aperture_radius`, in focus at the target's
        distance unless `focus_distance` says otherwise."""
        if focus_distance is None:
            focus_distance = float(np.linalg.norm(np.subtract(target, position)))
        return super().looking_at(
            position, target, up, vfov_degrees, aperture_radius=aperture_radius, focus_distance=focus_distance
        )

    def fill_frame(self, record: np.ndarray, width: int, height: int) -> None:
        super().fill_frame(record, width, height)
        record["aperture_radius"], record["focus_distance"] = self.aperture_radius, self.focus_distance

    def mitsuba_sensor(self, width: int, height: int) -> dict:
        sensor = super().mitsuba_sensor(width, height)
        return {
            **sensor,
            "type": "thinlens",
            "aperture_radius": self.aperture_radius,
            "focus_distance": self.focus_distance,
        }
