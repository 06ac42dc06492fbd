"""Fly-camera navigation: W/A/S/D/Q/E move, a mouse drag turns, the wheel changes speed, R resets,
F frames the whole scene. Pure numpy: the viewer feeds it events and asks for the camera."""

from __future__ import annotations

import math

import numpy as np

from ..scene import Camera

# Radians the view turns per pixel of mouse drag.
LOOK_RADIANS_PER_PIXEL = 0.004
# The view stops this short of straight up or down, where "right" would be undefined.
PITCH_LIMIT = math.radians(89.0)
# One wheel notch (100 units of rendercanvas's wheel dy) multiplies the speed by this.
SPEED_STEP = 1.25
WHEEL_NOTCH = 100.0
# The starting speed crosses the scene's bounding box diagonal in this many seconds.
SECONDS_TO_CROSS_SCENE = 4.0
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
    """Position, yaw and pitch about the scene camera's up vector, and a speed in scene units/s."""

    def __init__(self, camera: Camera, bounds: tuple[np.ndarray, np.ndarray]) -> None:
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
        """Back to the scene's own camera and the starting speed."""
        forward = np.asarray(self.home.forward)
        self.position = np.asarray(self.home.position, np.float64)
        self.yaw = 0.0
        self.pitch = math.asin(float(np.clip(forward.dot(self.world_up), -1.0, 1.0)))
        self.speed = self.scene_size / SECONDS_TO_CROSS_SCENE

    @property
    def forward(self) -> np.ndarray:
        horizontal = math.cos(self.yaw) * self._reference_forward + math.sin(self.yaw) * self._reference_right
        return math.cos(self.pitch) * horizontal + math.sin(self.pitch) * self.world_up

    def camera(self) -> Camera:
        return Camera(tuple(self.position), tuple(self.forward), tuple(self.world_up), self.home.vfov_degrees)

    def frame_scene(self, aspect: float) -> None:
        """Keep the direction, step back until the scene's bounding sphere fills the view."""
        centre = (self.bounds[0] + self.bounds[1]) / 2
        radius = self.scene_size / 2
        half_vertical = math.radians(self.home.vfov_degrees) / 2
        half_horizontal = math.atan(math.tan(half_vertical) * aspect)
        distance = radius / math.sin(min(half_vertical, half_horizontal))
        self.position = centre - distance * self.forward

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
