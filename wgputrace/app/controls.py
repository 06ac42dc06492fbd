"""Fly-camera navigation: W/A/S/D/Q/E move, a mouse drag turns, the wheel changes speed, R resets,
F frames the whole scene; the lens: its aperture opened and closed in steps, its focus set to a
distance. Pure numpy: the viewer feeds it events and asks for the camera."""

from __future__ import annotations

import math

import numpy as np

from ..scene import Camera, Sensor, ThinLensCamera

# Radians the view turns per pixel of mouse drag.
LOOK_RADIANS_PER_PIXEL = 0.004
# The view stops this short of straight up or down, where "right" would be undefined.
PITCH_LIMIT = math.radians(89.0)
# One wheel notch (100 units of rendercanvas's wheel dy) multiplies the speed by this.
SPEED_STEP = 1.25
WHEEL_NOTCH = 100.0
# The starting speed crosses the scene's bounding box diagonal in this many seconds.
SECONDS_TO_CROSS_SCENE = 4.0
# The first step of the aperture key opens the pinhole to a lens of this fraction of the scene's
# size in radius; each step more multiplies the radius by APERTURE_STEP, each step less divides it,
# and a step below the first closes the lens to the pinhole again (whose kernel draws no lens sample).
APERTURE_FIRST_FRACTION = 0.004
APERTURE_STEP = 1.5
# Before a click sets it, a lens opened on a pinhole focuses this far along forward from the camera
# to the scene's centre, and never nearer than this fraction of the scene's size.
NEAREST_FOCUS_FRACTION = 0.01
# Key -> (right, up, forward) direction of movement.
MOVE_KEYS = {
    "w": (0, 0, 1),
    "s": (0, 0, -1),
    "d": (1, 0, 0),
    "a": (-1, 0, 0),
    "e": (0, 1, 0),
    "q": (0, -1, 0),
}


class FlyCamera:
    """Position, yaw and pitch about the scene camera's up vector, a speed in scene units/s, and the
    camera's kind and parameters (`optics`: the scene's camera until the lens is opened, closed,
    focused or the view framed)."""

    def __init__(self, camera: Sensor, bounds: tuple[np.ndarray, np.ndarray]) -> None:
        self.home = camera
        self.bounds = (np.asarray(bounds[0], np.float64), np.asarray(bounds[1], np.float64))
        self.world_up = np.asarray(camera.up) / np.linalg.norm(camera.up)
        forward = np.asarray(camera.forward)
        # yaw 0 looks along the home forward's horizontal part
        horizontal = forward - forward.dot(self.world_up) * self.world_up
        self._reference_forward = horizontal / np.linalg.norm(horizontal)
        self._reference_right = np.cross(self._reference_forward, self.world_up)
        # key -> when it was pressed or last counted; seconds held along (right, up, forward) not yet moved
        self._held_since: dict[str, float] = {}
        self._pending = np.zeros(3)
        self.reset()

    @property
    def scene_size(self) -> float:
        return float(np.linalg.norm(self.bounds[1] - self.bounds[0])) or 1.0

    def reset(self) -> None:
        """Back to the scene's own camera, its lens and the starting speed."""
        forward = np.asarray(self.home.forward)
        self.position = np.asarray(self.home.position, np.float64)
        self.yaw = 0.0
        self.pitch = math.asin(float(np.clip(forward.dot(self.world_up), -1.0, 1.0)))
        self.speed = self.scene_size / SECONDS_TO_CROSS_SCENE
        self.optics = self.home
        if isinstance(self.home, ThinLensCamera):
            self.focus_distance = self.home.focus_distance
        else:
            centre = (self.bounds[0] + self.bounds[1]) / 2 - self.position
            self.focus_distance = max(float(centre @ forward), NEAREST_FOCUS_FRACTION * self.scene_size)

    @property
    def forward(self) -> np.ndarray:
        horizontal = math.cos(self.yaw) * self._reference_forward + math.sin(self.yaw) * self._reference_right
        return math.cos(self.pitch) * horizontal + math.sin(self.pitch) * self.world_up

    def camera(self) -> Sensor:
        return self.optics.posed(tuple(self.position), tuple(self.forward), tuple(self.world_up))

    def frame_scene(self, aspect: float) -> None:
        """Keep the direction, step back until the scene's bounding sphere fills the view (`Sensor.framed`)."""
        centre = (self.bounds[0] + self.bounds[1]) / 2
        distance, self.optics = self.optics.framed(self.scene_size / 2, aspect)
        self.position = centre - distance * self.forward

    @property
    def aperture_radius(self) -> float | None:
        """The lens's radius (0 for the pinhole); None for a camera without a lens to open."""
        if isinstance(self.optics, ThinLensCamera):
            return self.optics.aperture_radius
        return 0.0 if isinstance(self.optics, Camera) else None

    def step_aperture(self, steps: int) -> bool:
        """Open (steps > 0) or close the lens by APERTURE_STEP per step, from and down to the pinhole;
        False where the camera has no lens to open (orthographic, equirectangular)."""
        radius = self.aperture_radius
        if radius is None:
            return False
        first = APERTURE_FIRST_FRACTION * self.scene_size
        radius = first * APERTURE_STEP ** (steps - 1) if radius == 0.0 else radius * APERTURE_STEP**steps
        # below the first step (halfway there in steps, so that rounding cannot close it) is the pinhole
        self._lens(0.0 if radius < first / math.sqrt(APERTURE_STEP) else radius)
        return True

    def focus_at(self, distance: float) -> None:
        """Focus the lens (the one to come, while the pinhole is shown) at `distance` along forward."""
        self.focus_distance = max(float(distance), NEAREST_FOCUS_FRACTION * self.scene_size)
        if isinstance(self.optics, ThinLensCamera):
            self._lens(self.optics.aperture_radius)

    def _lens(self, aperture_radius: float) -> None:
        """The perspective camera's kind for a lens of `aperture_radius`: the pinhole at 0."""
        pose = (self.optics.position, self.optics.forward, self.optics.up, self.optics.vfov_degrees)
        if aperture_radius == 0.0:
            self.optics = Camera(*pose)
        else:
            self.optics = ThinLensCamera(*pose, aperture_radius=aperture_radius, focus_distance=self.focus_distance)

    def look(self, dx: float, dy: float) -> None:
        """Turn by a mouse drag of (dx, dy) pixels: right turns right, up looks up."""
        self.yaw += dx * LOOK_RADIANS_PER_PIXEL
        self.pitch = float(np.clip(self.pitch - dy * LOOK_RADIANS_PER_PIXEL, -PITCH_LIMIT, PITCH_LIMIT))

    def wheel(self, dy: float) -> None:
        """Scrolling up (negative dy) speeds up, down slows down."""
        self.speed *= SPEED_STEP ** (-dy / WHEEL_NOTCH)

    def press(self, key: str, now: float) -> None:
        if key in MOVE_KEYS and key not in self._held_since:
            self._held_since[key] = now

    def release(self, key: str, now: float) -> None:
        """A key let go counts for the time it was held, even if no frame ran meanwhile."""
        since = self._held_since.pop(key, None)
        if since is not None:
            self._pending += np.asarray(MOVE_KEYS[key]) * max(now - since, 0.0)

    def move(self, now: float) -> bool:
        """Move for the time movement keys were held up to `now` (wall time, however long the
        frames are); whether the camera moved."""
        for key, since in self._held_since.items():
            self._pending += np.asarray(MOVE_KEYS[key]) * max(now - since, 0.0)
            self._held_since[key] = now
        if not self._pending.any():
            return False
        forward = self.forward
        right = np.cross(forward, self.world_up)
        right /= np.linalg.norm(right)
        seconds_right, seconds_up, seconds_forward = self._pending
        self.position = self.position + self.speed * (
            seconds_right * right + seconds_up * self.world_up + seconds_forward * forward
        )
        self._pending = np.zeros(3)
        return True
