"""Keys and the mouse: rendercanvas's events turned into what they do to the viewer. HELP, which the
overlay shows, lists the keys; FlyCamera turns held keys and drags into camera motion; a click (a
press and release of the left button that did not drag) focuses the lens there."""

from __future__ import annotations

import time
from dataclasses import replace

from ..image_io import TONEMAP_OPERATORS
from ..view.layout import View
from .controls import MOVE_KEYS

# The exposure keys' step, in stops.
EXPOSURE_STEP_EV = 0.5
# A left-button press and release this close together (pixels, either way) is a click, not a drag.
CLICK_PIXELS = 3.0
# Aperture keys: the lens opens and closes by a step of FlyCamera.step_aperture.
APERTURE_KEYS = {",": -1, ".": 1}
# Shift+D switches the denoiser: a plain d moves the camera right (W A S D).
DENOISER_KEY = "D"
VIEW_KEYS = {"1": View.RADIANCE, "2": View.NORMAL, "3": View.ALBEDO, "4": View.DEPTH, "5": View.HEAT}
HELP = (
    "WASDQE move, drag look, wheel speed, R reset, F frame the scene, click focus, , . aperture",
    "1-5 views, V moving-picture views, N filter, Shift+D denoiser, B boxes, [ ] box level, P screenshot, "
    "Space pause, Tab info",
    "+/- exposure, X auto-exposure, T tone curve, C the scene file's next camera",
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
        self._pressed_at = (0.0, 0.0)

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
            self._pressed_at = self._pointer
        elif kind == "pointer_up" and event.get("button") == 1:
            self._dragging = False
            moved = max(abs(event["x"] - self._pressed_at[0]), abs(event["y"] - self._pressed_at[1]))
            if moved <= CLICK_PIXELS:
                viewer.focus_at(event["x"], event["y"])
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
        elif key == "v":
            viewer.next_frame_view()
        elif key == "n":
            settings.filter_enabled = not settings.filter_enabled
        elif key == "b":
            viewer.boxes.toggle(presenter, viewer.view)
        elif key in ("[", "]") and viewer.view is not None:
            viewer.boxes.step(1 if key == "]" else -1, presenter, viewer.view)
        elif key in ("+", "="):
            viewer.tone = replace(viewer.tone, ev=viewer.tone.ev + EXPOSURE_STEP_EV)
        elif key == "-":
            viewer.tone = replace(viewer.tone, ev=viewer.tone.ev - EXPOSURE_STEP_EV)
        elif key == "x":
            viewer.tone = replace(viewer.tone, automatic=not viewer.tone.automatic)
        elif key == "t":
            following = (TONEMAP_OPERATORS.index(viewer.tone.operator) + 1) % len(TONEMAP_OPERATORS)
            viewer.tone = replace(viewer.tone, operator=TONEMAP_OPERATORS[following])
        elif controller is not None and key in APERTURE_KEYS:
            if controller.step_aperture(APERTURE_KEYS[key]):
                viewer.pacing.camera_turned()
            else:
                viewer.overlay.show_status(f"the {type(controller.optics).__name__} has no lens to open")
        elif key == "p":
            viewer.screenshot()
        elif controller is not None and key == "r":
            controller.reset()
            viewer.pacing.camera_turned()
        elif controller is not None and key == "c":
            viewer.overlay.show_status(viewer.shown.next_camera())
            viewer.pacing.camera_turned()
        elif controller is not None and key == "f":
            width, height = viewer.canvas.get_physical_size()
            controller.frame_scene(width / max(height, 1))
            viewer.pacing.camera_turned()
        viewer.overlay.redraw_soon()
