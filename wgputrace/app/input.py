"""Keys and the mouse: rendercanvas's events turned into what they do to the viewer. HELP, which the
overlay shows, lists the keys; FlyCamera turns held keys and drags into camera motion."""

from __future__ import annotations

import time

from ..view.layout import View
from .controls import MOVE_KEYS

EXPOSURE_STEP = 2.0**0.5
# Shift+D switches the denoiser: a plain d moves the camera right (W A S D).
DENOISER_KEY = "D"
VIEW_KEYS = {"1": View.RADIANCE, "2": View.NORMAL, "3": View.ALBEDO, "4": View.DEPTH, "5": View.HEAT}
HELP = (
    "WASDQE move, drag look, wheel speed, R reset, F frame the scene",
    "1-5 views, N filter, Shift+D denoiser, B boxes, [ ] box level, P screenshot, +/- exposure, Space pause, Tab info",
)
EVENT_TYPES = ("key_down", "key_up", "pointer_down", "pointer_up", "pointer_move", "wheel")


def _normalized(key: str) -> str:
    """Letters in lower case (Shift held gives capitals: Shift+W moves as W does); named keys ("Tab") as they are."""
    return key.lower() if len(key) == 1 else key


class ViewerInput:
    """What each event of EVENT_TYPES does to `viewer`; a drag with the left button turns the camera."""

    def __init__(self, viewer) -> None:
        self.viewer = viewer
        self._dragging = False
        self._pointer = (0.0, 0.0)

    def on_event(self, event: dict) -> None:
        viewer = self.viewer
        kind = event["event_type"]
        if kind == "key_down":
            self.press(event["key"])
        elif kind == "key_up":
            if viewer.controller is not None:
                viewer.controller.release(_normalized(event["key"]), time.perf_counter())
        elif kind == "pointer_down" and event.get("button") == 1:
            self._dragging, self._pointer = True, (event["x"], event["y"])
        elif kind == "pointer_up" and event.get("button") == 1:
            self._dragging = False
        elif kind == "pointer_move" and self._dragging:
            self.look(event["x"] - self._pointer[0], event["y"] - self._pointer[1])
            self._pointer = (event["x"], event["y"])
        elif kind == "wheel" and viewer.controller is not None:
            viewer.controller.wheel(event["dy"])
            viewer.overlay.redraw_soon()

    def look(self, dx: float, dy: float) -> None:
        """Turn as a mouse drag of (dx, dy) pixels does."""
        viewer = self.viewer
        if viewer.controller is not None:
            viewer.controller.look(dx, dy)
            viewer.pacing.camera_turned()

    def press(self, key: str) -> None:
        """Do what pressing `key` (rendercanvas's name: "w", "D", "Tab") does."""
        viewer = self.viewer
        if key == DENOISER_KEY:
            viewer.denoiser.on = not viewer.denoiser.on
            if viewer.denoiser.on:
                viewer.start_denoiser()
            viewer.overlay.redraw_soon()
            return
        key = _normalized(key)
        controller, settings, presenter = viewer.controller, viewer.settings, viewer.device.presenter
        if controller is not None and key in MOVE_KEYS:
            controller.press(key, time.perf_counter())
        elif key == "Escape":
            viewer.canvas.close()
        elif key == "Tab":
            viewer.overlay.show_info = not viewer.overlay.show_info
        elif key == " ":
            viewer.paused = not viewer.paused
        elif key in VIEW_KEYS:
            settings.view = VIEW_KEYS[key]
        elif key == "n":
            settings.filter_enabled = not settings.filter_enabled
        elif key == "b":
            viewer.boxes.toggle(presenter, viewer.view)
        elif key in ("[", "]") and viewer.view is not None:
            viewer.boxes.step(1 if key == "]" else -1, presenter, viewer.view)
        elif key in ("+", "="):
            viewer.exposure *= EXPOSURE_STEP
        elif key == "-":
            viewer.exposure /= EXPOSURE_STEP
        elif key == "p":
            viewer.screenshot()
        elif controller is not None and key == "r":
            controller.reset()
            viewer.pacing.camera_turned()
        elif controller is not None and key == "f":
            width, height = viewer.canvas.get_physical_size()
            controller.frame_scene(width / max(height, 1))
            viewer.pacing.camera_turned()
        viewer.overlay.redraw_soon()
