"""The interactive viewer: a progressive path-traced picture in a window, navigation, debug views,
the pre-convergence filter, the denoiser and screenshots.

Every frame adds samples on the GPU and presents the accumulation through tone mapping and sRGB
on the GPU; nothing is read back to Python except for screenshots. While the camera moves, the
viewer traces a reduced resolution, one sample per pixel, chosen so a frame holds the target
frame time; once the camera has rested for REST_SECONDS it traces the full resolution, adding as
many samples (or rows of a sample) per frame as fit the same budget.

With the denoiser on (Shift+D), Intel Open Image Denoise's picture of the resting camera's
samples is shown once it is ready (view/denoised.py makes it in the background, again as the
samples grow); while the camera moves, and wherever OIDN is not installed, the a-trous filter's
picture is shown instead.

What fails keeps the picture: a scene file that does not load, or a scene (or window size) the
device cannot hold (DeviceLimitError, GpuFailure), is reported in the overlay and on the console
while the viewer keeps showing what it showed. A lost device is replaced by a new one (gpu()) and
everything drawn on it made again; where no new device can be had, the viewer says why in one
line and closes with exit status 1.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..bvh.levels import box_edges, node_levels
from ..cli_arguments import apply_lighting
from ..denoise import DenoiserMissing, denoiser_device
from ..gpu.device import DeviceLimitError, GpuFailure, gpu, reporting
from ..gpu.graphics import image_texture, read_texture
from ..image_io import save_image
from ..loaders import load_scene, scene_file
from ..render import Renderer
from ..scenes import DEFAULT_SCENE
from ..view.banded import BandedRenderer
from ..view.denoised import DenoisedPicture, DenoiseFailure
from ..view.display import Display, ViewSettings
from ..view.layout import IMAGE_FORMAT, View
from ..view.present import Presenter
from .controls import MOVE_KEYS, FlyCamera
from .overlay import text_overlay

TARGET_FPS = 20.0
# Part of a frame kept for resolving, filtering, presenting and events, until measured.
INITIAL_OVERHEAD_SECONDS = 0.01
# Tracing gets at least this much of every frame, however slow presenting is.
MIN_TRACE_SECONDS = 0.005
# The camera counts as resting once it has not changed for this long.
REST_SECONDS = 0.25
# While moving the traced image is at least 1/MAX_PREVIEW_SCALE of the window in each direction.
MAX_PREVIEW_SCALE = 16
# Before the first frame has measured the adapter, the preview starts this coarse.
UNMEASURED_PREVIEW_SCALE = 8
# The overlay's text is redrawn this often (Pillow costs milliseconds; per frame would show in the fps).
OVERLAY_SECONDS = 0.25
# A scene file is checked for changes this often.
SCENE_POLL_SECONDS = 0.5
# The fps shown and the per-frame cost besides tracing follow each frame by this fraction
# (smoothing over about ten frames).
FRAME_SMOOTHING = 0.1
# `frames` keeps at most this many records (a long session would otherwise grow it without end).
FRAME_LOG_LIMIT = 100_000
EXPOSURE_STEP = 2.0**0.5
STATUS_SECONDS = 4.0
OVERLAY_POSITION = (8, 8)

# Shift+D switches the denoiser: a plain d moves the camera right (W A S D).
DENOISER_KEY = "D"
VIEW_KEYS = {"1": View.RADIANCE, "2": View.NORMAL, "3": View.ALBEDO, "4": View.DEPTH, "5": View.HEAT}
HELP = (
    "WASDQE move, drag look, wheel speed, R reset, F frame the scene",
    "1-5 views, N filter, Shift+D denoiser, B boxes, [ ] box level, P screenshot, +/- exposure, Space pause, Tab info",
)


@dataclass
class ViewerOptions:
    scene: str = DEFAULT_SCENE
    size: tuple[int, int] = (640, 480)
    max_depth: int = 9
    seed: int = 1
    exposure: float = 1.0
    target_fps: float = TARGET_FPS
    filter: bool = False
    denoise: bool = False
    # --env, --env-intensity, --env-rotation as cli_arguments.apply_lighting reads them
    env: str | tuple[float, float, float] | Path | None = None
    env_intensity: float | None = None
    env_rotation: float | None = None
    info: bool = True
    screenshot_dir: Path = field(default_factory=Path.cwd)


@dataclass
class FrameRecord:
    """One presented frame, for benchmarks and tests."""

    seconds: float  # wall time since the previous frame ended
    trace_seconds: float
    traced_size: tuple[int, int]
    samples_per_pixel: float
    moving: bool


def _modified_time(spec: str) -> float | None:
    """When the scene file `spec` names last changed (None for a built-in scene or an unreadable file)."""
    path = scene_file(spec)
    try:
        return None if path is None else path.stat().st_mtime
    except OSError:
        return None


def _normalized(key: str) -> str:
    """Letters in lower case (Shift held gives capitals: Shift+W moves as W does); named keys ("Tab") as they are."""
    return key.lower() if len(key) == 1 else key


class SceneView:
    """Everything that depends on the scene and the window size: renderer, bands, display, and the
    denoised picture once the denoiser has been on (`denoiser_device`: OIDN's device)."""

    def __init__(self, scene, size: tuple[int, int], options: ViewerOptions, denoiser_device: str | None) -> None:
        guides = denoiser_device is not None
        self.renderer = Renderer(scene, size[0], size[1], seed=options.seed, max_depth=options.max_depth, guides=guides)
        self.banded = BandedRenderer(self.renderer)
        self.display = Display(self.banded)
        self.denoised = DenoisedPicture(self.banded, denoiser_device) if guides else None
        # the binary tree's levels: the GPU's 4-wide records are derived from it
        bvh = self.renderer.records.acceleration
        self.levels = node_levels(bvh.left_or_first, bvh.triangle_count)

    def start_denoiser(self, denoiser_device: str) -> None:
        """Accumulate the guides from now on (which restarts the samples) and make the denoised
        picture. The guides stay on when the denoiser is switched off: they cost no measurable
        time (a pass at 640x480 took 1.06 s with them, 1.05 s without, on lavapipe), and switching
        back then shows OIDN's picture of the same samples without starting again."""
        self.renderer.guides_enabled = True
        self.denoised = DenoisedPicture(self.banded, denoiser_device)


class Viewer:
    def __init__(self, canvas, options: ViewerOptions) -> None:
        self.canvas, self.options = canvas, options
        self.surface = canvas.get_context("wgpu")
        self._start_device()
        self.exit_status = 0  # 1 once the device was lost and no new one could be started
        self.settings = ViewSettings(filter_enabled=options.filter)
        self.denoising = options.denoise  # Shift+D: show OIDN's picture where it can be had
        self._denoiser_device: str | None = None  # OIDN's device, once asked for
        self.denoiser_missing: str | None = None  # why OIDN cannot run here, once asked for
        self.exposure = options.exposure
        self.show_info = options.info
        self.show_boxes = False
        self.paused = False  # Space: stop adding samples (the picture stays as it is)
        self.box_level = 0
        self.frames: list[FrameRecord] = []
        self.errors: list[str] = []
        self.status = ""
        self._status_until = 0.0
        self.scene = None
        # a reloaded scene not shown yet: it replaces `scene` once the device has taken its view
        self._incoming = None
        # a window size at which the device refused `scene`'s view: not tried again until it changes
        self._refused_size: tuple[int, int] | None = None
        self.view: SceneView | None = None
        self.controller: FlyCamera | None = None
        self._scene_time = _modified_time(options.scene)
        self._next_scene_poll = 0.0
        self._next_overlay = 0.0
        self._camera_changed = False
        self._moving = False
        self._last_change = 0.0
        self._dragging = False
        self._pointer = (0.0, 0.0)
        self._overhead = INITIAL_OVERHEAD_SECONDS
        self._frame_seconds: float | None = None
        self._last_frame = time.perf_counter()
        self._screenshots = 0
        self._load_scene()
        canvas.add_event_handler(
            self._on_event, "key_down", "key_up", "pointer_down", "pointer_up", "pointer_move", "wheel"
        )
        canvas.request_draw(self.draw)

    # device

    def _start_device(self) -> None:
        """Take gpu()'s device and make what draws on it: the surface's configuration, the
        presenter, the black frame shown with no scene."""
        self.context = gpu()
        target_format = self.surface.get_preferred_format(self.context.adapter)
        self.surface.configure(device=self.context.device, format=target_format)
        self.presenter = Presenter(self.context, target_format)
        self._black = image_texture(self.context, "black", 1, 1, IMAGE_FORMAT)

    def _replace_device(self, reason: str) -> None:
        """After a device loss: a new device and, at the next frame, the scene's view made on it
        (camera, settings and scene kept); or, where none can be started, one line and close."""
        print(f"wgputrace view: the GPU device was lost ({reason}); starting a new one", file=sys.stderr, flush=True)
        try:
            self._start_device()
        except RuntimeError as error:  # GpuFailure, or no adapter at all
            print(
                f"wgputrace view: error: the GPU device was lost ({reason}) and no new one could be started: {error}",
                file=sys.stderr,
                flush=True,
            )
            self.exit_status = 1
            self.canvas.close()
            return
        self.view, self._refused_size = None, None
        self._show_status(f"the GPU device was lost ({reason}) and replaced")

    # scene and size

    def _report(self, message: str) -> None:
        """A failure in red in the overlay and on the console; the scene shown, if any, stays."""
        print(f"wgputrace view: {message}", file=sys.stderr, flush=True)
        shown = [f"still showing the previous scene ({self.options.scene})"] if self.view is not None else []
        self.errors = [message] + shown
        self._next_overlay = 0.0

    def _load_scene(self) -> None:
        try:
            scene = load_scene(self.options.scene)
            note = apply_lighting(scene, self.options)
        except ValueError as error:  # SceneLoadError, or a bad --env map (SceneError)
            self._report(f"scene not loaded: {error}")
            return
        if note is not None:
            print(f"wgputrace view: {note}", file=sys.stderr, flush=True)
        if self.scene is None:
            self._adopt(scene)  # nothing shown yet, so nothing to keep
        else:
            self._incoming = scene

    def _adopt(self, scene) -> None:
        """Show `scene` from now on, from its own camera; its view is made at the next frame's size."""
        self.errors = []
        self.scene, self._incoming = scene, None
        self.controller = FlyCamera(scene.camera, scene.bounds())
        self.settings.depth_scale = self.controller.scene_size
        self.view, self._refused_size = None, None
        self._next_overlay = 0.0

    def _poll_scene_file(self, now: float) -> None:
        if now < self._next_scene_poll:
            return
        self._next_scene_poll = now + SCENE_POLL_SECONDS
        changed = _modified_time(self.options.scene)
        if changed is not None and changed != self._scene_time:
            self._scene_time = changed
            print(f"wgputrace view: {self.options.scene} changed, reloading", file=sys.stderr, flush=True)
            self._load_scene()

    def _ensure_view(self, size: tuple[int, int]) -> None:
        """A view of the incoming scene, or of the scene shown at a new window size; where the
        device refuses it, the view (and scene) shown before stay."""
        incoming = self._incoming is not None
        shown_size = None if self.view is None else (self.view.renderer.width, self.view.renderer.height)
        if not incoming and size in (shown_size, self._refused_size):
            return
        try:
            denoiser = self._oidn_device() if self.denoising else None
            view = SceneView(self._incoming if incoming else self.scene, size, self.options, denoiser)
        except (DeviceLimitError, GpuFailure) as error:
            if isinstance(error, GpuFailure) and self.context.lost_reason is not None:
                raise  # draw() replaces the device, then the view is made again
            if incoming:
                self._incoming = None
            else:
                self._refused_size = size
            self._report(f"scene not shown at {size[0]}x{size[1]}: {error}")
            return
        if incoming:
            self._adopt(self._incoming)
        self.view, self._refused_size = view, None
        self._update_boxes()
        # start as if the camera had just moved: a reduced picture first, then the full one
        self._restart(time.perf_counter(), moving=True)

    # navigation and keys

    def _on_event(self, event: dict) -> None:
        kind = event["event_type"]
        if kind == "key_down":
            self.press(event["key"])
        elif kind == "key_up":
            if self.controller is not None:
                self.controller.release(_normalized(event["key"]), time.perf_counter())
        elif kind == "pointer_down" and event.get("button") == 1:
            self._dragging, self._pointer = True, (event["x"], event["y"])
        elif kind == "pointer_up" and event.get("button") == 1:
            self._dragging = False
        elif kind == "pointer_move" and self._dragging:
            self.look(event["x"] - self._pointer[0], event["y"] - self._pointer[1])
            self._pointer = (event["x"], event["y"])
        elif kind == "wheel" and self.controller is not None:
            self.controller.wheel(event["dy"])
            self._next_overlay = 0.0

    def look(self, dx: float, dy: float) -> None:
        """Turn as a mouse drag of (dx, dy) pixels does."""
        if self.controller is not None:
            self.controller.look(dx, dy)
            self._camera_changed = True

    def press(self, key: str) -> None:
        """Do what pressing `key` (rendercanvas's name: "w", "D", "Tab") does."""
        if key == DENOISER_KEY:
            self.denoising = not self.denoising
            if self.denoising:
                self._start_denoiser()
            self._next_overlay = 0.0
            return
        key = _normalized(key)
        if self.controller is not None and key in MOVE_KEYS:
            self.controller.press(key, time.perf_counter())
        elif key == "Escape":
            self.canvas.close()
        elif key == "Tab":
            self.show_info = not self.show_info
        elif key == " ":
            self.paused = not self.paused
        elif key in VIEW_KEYS:
            self.settings.view = VIEW_KEYS[key]
        elif key == "n":
            self.settings.filter_enabled = not self.settings.filter_enabled
        elif key == "b":
            self.show_boxes = not self.show_boxes
            self._update_boxes()
        elif key in ("[", "]") and self.view is not None:
            deepest = int(self.view.levels.max())
            self.box_level = min(max(self.box_level + (1 if key == "]" else -1), 0), deepest)
            self.show_boxes = True
            self._update_boxes()
        elif key in ("+", "="):
            self.exposure *= EXPOSURE_STEP
        elif key == "-":
            self.exposure /= EXPOSURE_STEP
        elif key == "p":
            self.screenshot()
        elif self.controller is not None and key == "r":
            self.controller.reset()
            self._camera_changed = True
        elif self.controller is not None and key == "f":
            width, height = self.canvas.get_physical_size()
            self.controller.frame_scene(width / max(height, 1))
            self._camera_changed = True
        self._next_overlay = 0.0

    # denoiser

    def _oidn_device(self) -> str | None:
        """OIDN's device ("CPU", "CUDA"), or None where it cannot run (`denoiser_missing` says why,
        once on the console too); asked once per viewer."""
        if self._denoiser_device is None and self.denoiser_missing is None:
            try:
                self._denoiser_device = denoiser_device()
            except DenoiserMissing as missing:
                self.denoiser_missing = str(missing)
                print(f"wgputrace view: {missing}; the a-trous filter serves instead", file=sys.stderr, flush=True)
        return self._denoiser_device

    def _start_denoiser(self) -> None:
        """Switch the guides on where OIDN can run and the view has none yet."""
        device = self._oidn_device()
        if device is None or self.view is None or self.view.denoised is not None:
            return
        # the samples so far have no guides and are dropped; resting, the picture they made stays
        # as the fallback until the first new pass is in
        self._restart(time.perf_counter(), moving=self._moving)
        self.view.start_denoiser(device)

    def _denoised(self) -> DenoisedPicture | None:
        """The denoised picture where the frame may show it: the denoiser on, the radiance view."""
        if not self.denoising or self.view is None or self.settings.view != View.RADIANCE:
            return None
        return self.view.denoised

    def _update_denoiser(self, now: float) -> None:
        denoised = self._denoised()
        if denoised is None:
            return
        try:
            denoised.update(now)
        except DenoiseFailure as failure:
            self.denoising = False
            print(f"wgputrace view: {failure}; the denoiser is off", file=sys.stderr, flush=True)
            self._show_status(f"{failure}; the denoiser is off")

    def _picture(self):
        """What the frame shows: the texture and the size of the image in it from its top-left
        corner. OIDN's picture where it is ready; else the resolved samples (_display_settings)."""
        view = self.view
        denoised = self._denoised()
        if denoised is not None and denoised.shown:
            return denoised.texture, view.banded.full_size
        return view.display.render(self._display_settings()), view.banded.size

    def _display_settings(self) -> ViewSettings:
        """The settings the resolved image is shown with: with the denoiser on, through the a-trous
        filter while the camera moves and wherever OIDN cannot run. Not at rest while OIDN's first
        picture is on its way: filtering the whole window every frame of the first full-size pass
        made that pass (and so the denoise) 5 times slower at 640x480 on lavapipe; the first pass
        comes in over the last filtered preview instead (the fallback)."""
        serves = self.denoising and (self._moving or self.view.denoised is None)
        return dataclasses.replace(self.settings, filter_enabled=True) if serves else self.settings

    def shown_label(self) -> str:
        """Which picture of the samples the radiance view shows: "OIDN (CPU), 16 spp", "a-trous" or "raw"."""
        denoised = self._denoised()
        if denoised is not None and denoised.shown:
            return denoised.label()
        return "a-trous" if self.view.display.filter_weight > 0.0 else "raw"

    def _denoiser_notice(self) -> list[str]:
        """The overlay's red line while Shift+D asks for a denoiser that cannot run here."""
        if self.denoising and self.denoiser_missing is not None:
            return [f"Shift+D: {self.denoiser_missing}; the a-trous filter serves instead"]
        return []

    def _update_boxes(self) -> None:
        if self.view is None or not self.show_boxes:
            self.presenter.set_box_lines(None)
            return
        bvh, level = self.view.renderer.records.acceleration, self.view.levels == self.box_level
        self.presenter.set_box_lines(box_edges(bvh.bounds_min[level], bvh.bounds_max[level]))

    # frames

    def _preview_size(self) -> tuple[int, int]:
        """The largest reduced size whose one sample per pixel fits the frame budget."""
        width, height = self.view.banded.full_size
        seconds_per_sample = self.view.banded.seconds_per_sample
        if seconds_per_sample is None:
            scale = UNMEASURED_PREVIEW_SCALE
        else:
            needed = width * height * seconds_per_sample / self._trace_budget()
            scale = min(max(math.ceil(math.sqrt(needed)), 2), MAX_PREVIEW_SCALE)
        return max(width // scale, 1), max(height // scale, 1)

    def _trace_budget(self) -> float:
        return max(1.0 / self.options.target_fps - self._overhead, MIN_TRACE_SECONDS)

    def _restart(self, now: float, *, moving: bool) -> None:
        camera = self.controller.camera()
        view = self.view
        if not moving and view.banded.samples_per_pixel > 0:
            radiance = dataclasses.replace(self._display_settings(), view=View.RADIANCE)
            view.display.render(radiance)
            view.display.keep_as_fallback(view.banded.size)
        view.banded.restart(camera, self._preview_size() if moving else None)
        view.display.camera_changed()
        if view.denoised is not None:
            view.denoised.camera_changed()
        width, height = view.banded.full_size
        self.presenter.set_camera(camera, width, height, self.controller.scene_size)
        self._moving = moving
        if moving:
            self._last_change = now

    def draw(self) -> None:
        """One frame: move, trace what fits the budget, resolve, present; a lost device is replaced."""
        try:
            with reporting("drawing a frame"):
                self._draw_frame()
        except GpuFailure:
            reason = self.context.lost_reason
            if reason is None:
                raise
            self._replace_device(reason)

    def _draw_frame(self) -> None:
        start = time.perf_counter()
        self._poll_scene_file(start)
        texture = self.surface.get_current_texture()
        size = (texture.size[0], texture.size[1])
        trace_seconds = 0.0
        image, image_size = self._black, (1, 1)
        if self.scene is not None and min(size) > 0:  # a minimized window has no pixels to trace
            self._ensure_view(size)
        if self.view is not None:
            moved = self.controller.move(start) or self._camera_changed
            self._camera_changed = False
            if moved:
                self._restart(start, moving=True)
            elif self._moving and start - self._last_change >= REST_SECONDS:
                self._restart(start, moving=False)
            banded = self.view.banded
            # a moving picture is always whole: one pass at the reduced size, chosen to fit
            if not self.paused:
                trace_seconds = banded.advance(self._trace_budget(), whole_pass=self._moving)
            self._update_denoiser(start)
            image, image_size = self._picture()
        if start >= self._next_overlay:
            self._refresh_overlay(start, size)
        exposure = self.exposure if self.settings.view == View.RADIANCE else 1.0
        self.presenter.draw(texture, image, image_size, exposure)
        end = time.perf_counter()
        self._overhead += FRAME_SMOOTHING * ((end - start - trace_seconds) - self._overhead)
        seconds = end - self._last_frame
        self._frame_seconds = (
            seconds
            if self._frame_seconds is None
            else self._frame_seconds + FRAME_SMOOTHING * (seconds - self._frame_seconds)
        )
        self._last_frame = end
        if self.view is not None:
            banded = self.view.banded
            if not self.frames:
                print(f"wgputrace view: showing {self.options.scene} in a {size[0]}x{size[1]} window", flush=True)
            self.frames.append(FrameRecord(seconds, trace_seconds, banded.size, banded.samples_done, self._moving))
            if len(self.frames) > FRAME_LOG_LIMIT:
                del self.frames[: FRAME_LOG_LIMIT // 2]

    # overlay and screenshots

    def info_lines(self) -> list[str]:
        fps = 0.0 if not self._frame_seconds else 1.0 / self._frame_seconds
        lines = [f"fps {fps:5.1f}   target {self.options.target_fps:g}"]
        if self.view is not None:
            banded, renderer = self.view.banded, self.view.renderer
            camera = self.controller.camera()
            samples_per_second = 0.0 if not banded.seconds_per_sample else 1.0 / banded.seconds_per_sample
            state = "moving" if self._moving else "resting"
            denoised = self.view.denoised
            lines += [
                f"{banded.samples_done:.2f} spp   {samples_per_second / 1e6:.3f} M samples/s   "
                f"tracing {banded.size[0]}x{banded.size[1]} of {banded.full_size[0]}x{banded.full_size[1]} ({state})",
                "camera ({:.3f}, {:.3f}, {:.3f})  dir ({:.3f}, {:.3f}, {:.3f})  speed {:.3g}/s".format(
                    *camera.position, *camera.forward, self.controller.speed
                ),
                f"scene {self.options.scene}: {renderer.triangle_count:,} triangles, "
                f"{renderer.records.acceleration.node_count:,} BVH nodes, depth {int(self.view.levels.max())}",
                f"view {self.settings.view.name.lower()}"
                + (f": {self.shown_label()}" if self.settings.view == View.RADIANCE else "")
                + "   filter "
                + (f"on (weight {self.view.display.filter_weight:.2f})" if self.settings.filter_enabled else "off")
                + "   denoiser "
                + ("on" if self.denoising else "off")
                + (
                    f" (last took {denoised.last_seconds:.2f} s)"
                    if self.denoising and denoised is not None and denoised.last_seconds is not None
                    else ""
                )
                + (f"   boxes level {self.box_level}" if self.show_boxes else "")
                + f"   exposure {self.exposure:.3g}"
                + ("   PAUSED" if self.paused else ""),
            ]
        lines += [f"adapter {self.context.adapter_name}", *HELP]
        return lines

    def _refresh_overlay(self, now: float, size: tuple[int, int]) -> None:
        self._next_overlay = now + OVERLAY_SECONDS
        lines = self.info_lines() if self.show_info else []
        if self.show_info and self.status and now < self._status_until:
            lines.append(self.status)
        errors = self.errors + self._denoiser_notice()
        if not lines and not errors:
            self.presenter.set_overlay(None)
            return
        max_width = max(size[0] - 2 * OVERLAY_POSITION[0], 1)
        self.presenter.set_overlay(text_overlay(lines, errors, max_width), OVERLAY_POSITION)

    def _show_status(self, message: str) -> None:
        """A line under the overlay's information for STATUS_SECONDS."""
        self.status = message
        self._status_until = time.perf_counter() + STATUS_SECONDS
        self._next_overlay = 0.0

    def screenshot(self) -> tuple[Path, Path] | None:
        """Save what the window shows (without the overlay) as PNG, and the linear image as EXR."""
        if self.view is None:
            return None
        banded = self.view.banded
        image, image_size = self._picture()
        size = self.canvas.get_physical_size()
        exposure = self.exposure if self.settings.view == View.RADIANCE else 1.0
        pixels = self.presenter.screenshot(image, image_size, size, exposure)
        linear = read_texture(self.context, image, np.float32, 4, image_size)[:, :, :3].copy()
        self.options.screenshot_dir.mkdir(parents=True, exist_ok=True)
        stem = self.options.screenshot_dir / f"wgputrace-{Path(self.options.scene).stem}-{self._screenshots:03d}"
        self._screenshots += 1
        from PIL import Image

        png = stem.with_suffix(".png")
        Image.fromarray(pixels).save(png)
        exr = save_image(stem.with_suffix(".exr"), linear)
        shown = self.shown_label() if self.settings.view == View.RADIANCE else self.settings.view.name.lower()
        self._show_status(f"saved {png.name} and {exr.name} at {banded.samples_done:.2f} spp ({shown})")
        camera = self.controller.camera()
        print(
            f"wgputrace view: saved {png} and {exr}: {banded.samples_done:.3f} spp at "
            f"{image_size[0]}x{image_size[1]}, camera {' '.join(f'{v:.9g}' for v in camera.position)} "
            f"dir {' '.join(f'{v:.9g}' for v in camera.forward)} speed {self.controller.speed:.9g} (showing {shown})",
            flush=True,
        )
        return png, Path(exr)
