"""What fails keeps the picture. A lost device is replaced by a new one (ViewerDevice.replace) and
everything drawn on it made again. A scene file that does not load, or a scene (or window size)
the device cannot hold (DeviceLimitError, GpuFailure), is reported in the overlay and on the
console while the scene shown stays (ShownScene)."""

from __future__ import annotations

import sys
from collections.abc import Callable

from ..cli_arguments import apply_lighting
from ..gpu.device import DeviceLimitError, GpuFailure, gpu
from ..gpu.graphics import image_texture
from ..loaders import load_scene, scene_file
from ..view.layout import IMAGE_FORMAT
from ..view.present import Presenter
from .controls import FlyCamera
from .options import ViewerOptions
from .scene_view import SceneView

# A scene file is checked for changes this often.
SCENE_POLL_SECONDS = 0.5


def _modified_time(spec: str) -> float | None:
    """When the scene file `spec` names last changed (None for a built-in scene or an unreadable file)."""
    path = scene_file(spec)
    try:
        return None if path is None else path.stat().st_mtime
    except OSError:
        return None


class ViewerDevice:
    """gpu()'s device and what draws on it: the surface's configuration, the presenter, the black
    frame shown with no scene."""

    def __init__(self, surface) -> None:
        self.surface = surface
        self._start()

    def _start(self) -> None:
        self.context = gpu()
        target_format = self.surface.get_preferred_format(self.context.adapter)
        self.surface.configure(device=self.context.device, format=target_format)
        self.presenter = Presenter(self.context, target_format)
        self.black = image_texture(self.context, "black", 1, 1, IMAGE_FORMAT)

    def replace(self, reason: str) -> bool:
        """After a device loss, a new device; where none can be started, one line saying why and False."""
        print(f"wgputrace view: the GPU device was lost ({reason}); starting a new one", file=sys.stderr, flush=True)
        try:
            self._start()
        except RuntimeError as error:  # GpuFailure, or no adapter at all
            print(
                f"wgputrace view: error: the GPU device was lost ({reason}) and no new one could be started: {error}",
                file=sys.stderr,
                flush=True,
            )
            return False
        return True


class ShownScene:
    """The scene shown, its camera controller and its view at the window's size. The scene file is
    polled; a reload waits as `incoming` until the device has taken its view. What fails is in
    `errors` (the overlay's red lines), and what was shown stays; `redraw` tells the overlay."""

    def __init__(self, options: ViewerOptions, device: ViewerDevice, redraw: Callable[[], None]) -> None:
        self.options, self.device, self._redraw = options, device, redraw
        self.scene = None
        self.incoming = None
        self.view: SceneView | None = None
        self.controller: FlyCamera | None = None
        # which of the scene's own cameras (Scene.cameras) is shown; -1: none of them
        self.camera_index = -1
        self.errors: list[str] = []
        # a window size at which the device refused `scene`'s view: not tried again until it changes
        self._refused_size: tuple[int, int] | None = None
        self._modified = _modified_time(options.scene)
        self.next_poll = 0.0

    def _report(self, message: str) -> None:
        """A failure in red in the overlay and on the console; the scene shown, if any, stays."""
        print(f"wgputrace view: {message}", file=sys.stderr, flush=True)
        shown = [f"still showing the previous scene ({self.options.scene})"] if self.view is not None else []
        self.errors = [message] + shown
        self._redraw()

    def load(self) -> None:
        """Read the scene file (or built-in scene); the first scene is shown at once, a reload once
        the device has taken its view."""
        try:
            scene = load_scene(self.options.scene, camera=self.options.camera)
            note = apply_lighting(scene, self.options)
        except ValueError as error:  # SceneLoadError, or a bad --env map (SceneError)
            self._report(f"scene not loaded: {error}")
            return
        if note is not None:
            print(f"wgputrace view: {note}", file=sys.stderr, flush=True)
        if self.scene is None:
            self._adopt(scene)  # nothing shown yet, so nothing to keep
        else:
            self.incoming = scene

    def _adopt(self, scene) -> None:
        """Show `scene` from now on, from its own camera; its view is made at the next frame's size."""
        self.errors = []
        self.scene, self.incoming = scene, None
        self.controller = FlyCamera(scene.camera, scene.bounds())
        self.camera_index = next((i for i, (_, camera) in enumerate(scene.cameras) if camera is scene.camera), -1)
        self.view, self._refused_size = None, None
        self._redraw()

    def next_camera(self) -> str:
        """Show the scene from the next of its own cameras (Scene.cameras, key C), from the first
        after the last; the overlay's status line saying which."""
        cameras = self.scene.cameras
        if not cameras:
            return "the scene brings no cameras of its own"
        self.camera_index = (self.camera_index + 1) % len(cameras)
        name, camera = cameras[self.camera_index]
        self.controller = FlyCamera(camera, self.scene.bounds())
        return f"camera {self.camera_index} of {len(cameras)}: {name}"

    def poll(self, now: float) -> None:
        """Reload the scene file if it changed (checked every SCENE_POLL_SECONDS)."""
        if now < self.next_poll:
            return
        self.next_poll = now + SCENE_POLL_SECONDS
        changed = _modified_time(self.options.scene)
        if changed is not None and changed != self._modified:
            self._modified = changed
            print(f"wgputrace view: {self.options.scene} changed, reloading", file=sys.stderr, flush=True)
            self.load()

    def ensure_view(self, size: tuple[int, int], make_view: Callable[..., SceneView]) -> bool:
        """A view (`make_view(scene, size)`) of the incoming scene, or of the scene shown at a new
        window size; whether one was made. Where the device refuses it, the view (and scene) shown
        before stay."""
        incoming = self.incoming is not None
        shown_size = None if self.view is None else (self.view.renderer.width, self.view.renderer.height)
        if not incoming and size in (shown_size, self._refused_size):
            return False
        try:
            view = make_view(self.incoming if incoming else self.scene, size)
        except (DeviceLimitError, GpuFailure) as error:
            if isinstance(error, GpuFailure) and self.device.context.lost_reason is not None:
                raise  # Viewer.draw replaces the device, then the view is made again
            if incoming:
                self.incoming = None
            else:
                self._refused_size = size
            self._report(f"scene not shown at {size[0]}x{size[1]}: {error}")
            return False
        if incoming:
            self._adopt(self.incoming)
        self.view, self._refused_size = view, None
        return True

    def device_replaced(self) -> None:
        """The view was made on a lost device: make it again at the next frame."""
        self.view, self._refused_size = None, None
