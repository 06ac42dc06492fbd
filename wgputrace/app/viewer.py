"""The interactive viewer: a progressive path-traced picture in a window. Every frame adds samples
on the GPU and presents them through exposure, a tone curve and sRGB on the GPU. While the camera
moves, each frame is a `Renderer.render_frame` whose pixels keep their samples across frames
(TemporalPicture, shown through the variance-guided filter; `--preview reset` brings back the
reduced-size preview that starts again on every move); at rest the full-size accumulation
converges, read back only for screenshots, a click's focus and OIDN. `Viewer` composes the parts,
each in its own module: FramePacing (frame budget, preview size, resting), ViewerInput (keys and
mouse), ViewerDevice and ShownScene (device loss, scene reloads, what fails keeps the picture),
ViewerDenoiser (Shift+D), Overlay, BoxLines and Screenshots."""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from ..cli_arguments import RESET_PREVIEW
from ..gpu.device import GpuFailure, reporting
from ..gpu.graphics import read_texture
from ..image_io import AUTO_EXPOSURE
from ..scene import Camera, Scene
from ..view.display import ViewSettings
from ..view.layout import View
from ..view.present import Tone
from ..view.temporal_picture import DEFAULT_FRAME_VIEW, TemporalPicture, next_frame_view
from .boxes import BoxLines
from .controls import FlyCamera
from .denoising import ViewerDenoiser
from .input import EVENT_TYPES, HELP, ViewerInput
from .options import ViewerOptions
from .overlay import Overlay
from .pacing import FramePacing, FrameRecord
from .recovery import ShownScene, ViewerDevice
from .scene_view import SceneView
from .screenshots import Screenshots


class Viewer:
    """The viewer drawing into `canvas` (a rendercanvas canvas) until it closes; `exit_status` is 1
    once the device was lost and no new one could be started."""

    def __init__(self, canvas, options: ViewerOptions) -> None:
        self.canvas, self.options = canvas, options
        self.device = ViewerDevice(canvas.get_context("wgpu"))
        self.exit_status = 0
        self.settings = ViewSettings(filter_enabled=options.filter)
        self.denoiser = ViewerDenoiser(options.denoise, self.settings)
        automatic = options.exposure == AUTO_EXPOSURE
        # how the radiance view is shown (keys +/-, X, T); the other views are shown as they are
        self.tone = Tone(options.tonemap, 0.0 if automatic else float(options.exposure), automatic)
        # when the auto-exposure last measured the picture (None: it starts again)
        self._exposure_measured_at: float | None = None
        self.paused = False  # Space: stop adding samples (the picture stays as it is)
        self.boxes = BoxLines()
        self.overlay = Overlay(options.info)
        self.shown = ShownScene(options, self.device, self.overlay.redraw_soon)
        self.pacing = FramePacing(options.target_fps)
        self.screenshots = Screenshots(options.screenshot_dir, options.scene)
        self.input = ViewerInput(self)
        self.shown.load()
        canvas.add_event_handler(self.input.on_event, *EVENT_TYPES)
        canvas.request_draw(self.draw)

    @property
    def scene(self) -> Scene | None:
        return self.shown.scene

    @property
    def view(self) -> SceneView | None:
        return self.shown.view

    @property
    def controller(self) -> FlyCamera | None:
        return self.shown.controller

    @property
    def errors(self) -> list[str]:
        return self.shown.errors

    @property
    def frames(self) -> list[FrameRecord]:
        return self.pacing.frames

    def _make_view(self, scene, size: tuple[int, int]) -> SceneView:
        return SceneView(scene, size, self.options, self.denoiser.wanted_device())

    def start_denoiser(self) -> None:
        """Switch the guides on where OIDN can run and the view has none yet."""
        device = self.denoiser.device()
        view = self.view
        if device is None or view is None or view.denoised is not None:
            return
        # the samples so far have no guides and are dropped; resting, the picture they made stays
        # as the fallback until the first new pass is in
        self._restart(time.perf_counter(), moving=self.pacing.moving)
        view.start_denoiser(device)

    def shown_label(self) -> str:
        """Which picture of the samples the radiance view shows: "OIDN (CPU), 16 spp", "a-trous" or
        "raw"; while moving, the moving picture's view ("SVGF filtered", "motion vectors", ...)."""
        moving = self._moving_picture()
        return self.settings.frame_view.value if moving is not None else self.denoiser.shown_label(self.view)

    def _moving_picture(self) -> TemporalPicture | None:
        """The moving picture where the frames show it: the radiance view of a view that has one
        (`SceneView.moving`), while the camera moves or a debug view (key V) is chosen."""
        view = self.view
        if view is None or view.moving is None or self.settings.view != View.RADIANCE or not self.pacing.moving:
            return None
        return view.moving

    def _frames_at_rest(self) -> bool:
        """Whether the moving picture goes on at rest: while a debug view of it is chosen."""
        view = self.view
        return view is not None and view.moving is not None and self.settings.frame_view != DEFAULT_FRAME_VIEW

    def next_frame_view(self) -> None:
        """Key V: the moving picture's next view, shown at rest too until the filtered one comes back."""
        view = self.view
        if view is None or view.moving is None:
            why = "--preview reset" if self.options.preview == RESET_PREVIEW else "this integrator has no G-buffer"
            self.overlay.show_status(f"no moving-picture views: {why}")
            return
        shown = self.settings.frame_view = next_frame_view(self.settings.frame_view)
        if not self.pacing.moving:
            self.pacing.camera_turned()  # start the frames again from the camera as it is
        self.overlay.show_status(f"moving picture: {shown.value}")

    def _picture(self):
        """What the frame shows: the texture and the size of the image in it from its top-left corner."""
        moving = self._moving_picture()
        if moving is not None:
            return moving.texture, moving.size
        return self.denoiser.picture(self.view, self.pacing.moving)

    def _samples_shown(self) -> float:
        """Samples per pixel of what is shown: the last frame's while the moving picture is."""
        moving = self._moving_picture()
        return moving.samples_per_pixel if moving is not None else self.view.banded.samples_done

    def _tone(self) -> Tone:
        moving = self._moving_picture()
        radiance = self.settings.view == View.RADIANCE and (moving is None or self.settings.frame_view.radiance)
        return self.tone if radiance else Tone()

    def _measure_exposure(self, image, image_size: tuple[int, int], now: float) -> None:
        """Where the auto-exposure is on, blend this frame's picture into its measurement."""
        if not self._tone().automatic:
            self._exposure_measured_at = None
            return
        last = self._exposure_measured_at
        seconds = 0.0 if last is None else now - last
        self.device.presenter.measure_exposure(image, image_size, seconds, restart=last is None)
        self._exposure_measured_at = now

    def focus_at(self, x: float, y: float) -> None:
        """Focus the lens at what the window shows at (x, y) (logical pixels): the first hit's
        distance (the guides' depth) along the camera's axis. Opens no lens: the aperture keys do."""
        view, controller = self.view, self.controller
        if view is None or controller is None:
            return
        camera = controller.camera()
        if not isinstance(camera, Camera):
            self.overlay.show_status(f"the {type(camera).__name__} has no lens to focus")
            return
        window = self.canvas.get_logical_size()
        width, height = view.banded.size
        column = min(max(int(x / max(window[0], 1) * width), 0), width - 1)
        row = min(max(int(y / max(window[1], 1) * height), 0), height - 1)
        depth = float(view.display.read_guides()["depth"][row, column])
        if not depth > 0.0:
            self.overlay.show_status("nothing there to focus on")
            return
        right, up, forward = camera.image_plane(width, height)
        ndc = ((column + 0.5) / width * 2.0 - 1.0, (row + 0.5) / height * 2.0 - 1.0)
        controller.focus_at(depth / float(np.linalg.norm(forward + ndc[0] * right - ndc[1] * up)))
        self.pacing.camera_turned()
        self.overlay.show_status(f"focus at {controller.focus_distance:.4g}")

    def _restart(self, now: float, *, moving: bool) -> None:
        """Start the samples again from the camera as it is: at full size at rest; while `moving`,
        the moving picture's frames (which keep their samples), or where the view has none, the
        bands at a reduced size. The last moving picture stays as the fallback of the first pass."""
        camera = self.controller.camera()
        view = self.view
        if not moving and view.moving is not None and self.pacing.moving:
            view.display.keep_as_fallback(view.banded.full_size, view.moving.texture)
        elif not moving and view.banded.samples_per_pixel > 0:
            radiance = dataclasses.replace(self.denoiser.display_settings(view, self.pacing.moving), view=View.RADIANCE)
            view.display.render(radiance)
            view.display.keep_as_fallback(view.banded.size)
        if not moving or view.moving is None:
            view.banded.restart(camera, self.pacing.preview_size(view.banded) if moving else None)
        view.display.camera_changed()
        if view.denoised is not None:
            view.denoised.camera_changed()
        width, height = view.banded.full_size
        self.device.presenter.set_camera(camera, width, height, self.controller.scene_size)
        self.pacing.restarted(now, moving=moving)

    def draw(self) -> None:
        """One frame: move, trace what fits the budget, resolve, present; a lost device is replaced."""
        try:
            with reporting("drawing a frame"):
                self._draw_frame()
        except GpuFailure:
            reason = self.device.context.lost_reason
            if reason is None:
                raise
            if not self.device.replace(reason):
                self.exit_status = 1
                self.canvas.close()
                return
            self.shown.device_replaced()
            self.overlay.show_status(f"the GPU device was lost ({reason}) and replaced")

    def _draw_frame(self) -> None:
        start = time.perf_counter()
        self.shown.poll(start)
        texture = self.device.surface.get_current_texture()
        size = (texture.size[0], texture.size[1])
        trace_seconds = setup_seconds = 0.0
        image, image_size = self.device.black, (1, 1)
        # a minimized window has no pixels to trace
        if self.scene is not None and min(size) > 0 and self.shown.ensure_view(size, self._make_view):
            # the view may be of a scene just loaded: the depth view's black is at its diagonal
            self.settings.depth_scale = self.controller.scene_size
            self.boxes.draw_on(self.device.presenter, self.view)
            # start as if the camera had just moved: a moving picture first, then the full one
            self._restart(time.perf_counter(), moving=True)
            setup_seconds = time.perf_counter() - start
        view = self.view
        if view is not None:
            if self.pacing.camera_moved(self.controller, start):
                self._restart(start, moving=True)
            elif self.pacing.rested(start) and not self._frames_at_rest():
                self._restart(start, moving=False)
            frames = view.moving is not None and self.pacing.moving
            if not self.paused and frames:
                camera, budget = self.controller.camera(), self.pacing.trace_budget()
                trace_seconds = view.moving.advance(camera, budget, self.settings.frame_view)
            elif not self.paused:
                # a reduced picture is always whole: one pass at the reduced size, chosen to fit
                trace_seconds = view.banded.advance(self.pacing.trace_budget(), whole_pass=self.pacing.moving)
            # OIDN denoises the resting samples, not the moving frames that share their buffers
            failure = self.denoiser.update(view, start, start=not frames)
            if failure is not None:
                self.overlay.show_status(failure)
            image, image_size = self._picture()
        if self.overlay.due(start):
            errors = self.errors + self.denoiser.notice()
            self.overlay.redraw(self.device.presenter, start, size, self.info_lines, errors)
        if view is not None:
            self._measure_exposure(image, image_size, start)
        self.device.presenter.draw(texture, image, image_size, self._tone())
        seconds = self.pacing.frame_done(start, time.perf_counter(), trace_seconds, setup_seconds)
        if view is not None:
            if not self.frames:
                print(f"wgputrace view: showing {self.options.scene} in a {size[0]}x{size[1]} window", flush=True)
            moving = view.moving if view.moving is not None and self.pacing.moving else None
            traced = view.banded.size if moving is None else moving.traced_size
            spp = view.banded.samples_done if moving is None else moving.samples_per_pixel
            upscale = 1 if moving is None else moving.upscale or 1
            self.pacing.record(FrameRecord(seconds, trace_seconds, traced, spp, self.pacing.moving, upscale))

    def info_lines(self) -> list[str]:
        """The overlay's information: frame rate, samples, camera, scene, what is shown, adapter, keys."""
        lines = [f"fps {self.pacing.fps:5.1f}   target {self.options.target_fps:g}"]
        view = self.view
        if view is not None:
            banded, renderer = view.banded, view.renderer
            camera = self.controller.camera()
            samples_per_second = 0.0 if not banded.seconds_per_sample else 1.0 / banded.seconds_per_sample
            state = "moving" if self.pacing.moving else "resting"
            moving = view.moving if view.moving is not None and self.pacing.moving else None
            tracing = (
                f"{banded.samples_done:.2f} spp   {samples_per_second / 1e6:.3f} M samples/s   "
                f"tracing {banded.size[0]}x{banded.size[1]} of {banded.full_size[0]}x{banded.full_size[1]} ({state})"
                if moving is None
                else f"{moving.samples_per_pixel} spp a frame, kept across frames   "
                f"{moving.size[0]}x{moving.size[1]} upscale {moving.upscale or 1} ({state}, frame {moving.frames})"
            )
            lines += [
                tracing,
                "camera ({:.3f}, {:.3f}, {:.3f})  dir ({:.3f}, {:.3f}, {:.3f})  speed {:.3g}/s  {}".format(
                    *camera.position, *camera.forward, self.controller.speed, self._lens_label()
                ),
                f"scene {self.options.scene}: {renderer.triangle_count:,} triangles, "
                f"{renderer.records.acceleration.node_count:,} BVH nodes, depth {int(view.levels.max())}   "
                f"integrator {renderer.integrator.name}",
                f"view {self.settings.view.name.lower()}"
                + (f": {self.shown_label()}" if self.settings.view == View.RADIANCE else "")
                + "   filter "
                + (f"on (weight {view.display.filter_weight:.2f})" if self.settings.filter_enabled else "off")
                + f"   denoiser {self.denoiser.state(view)}"
                + (f"   boxes level {self.boxes.level}" if self.boxes.shown else "")
                + f"   tone {self.tone.operator}  exposure {self.tone.ev:+.3g} EV"
                + (" auto" if self.tone.automatic else "")
                + ("   PAUSED" if self.paused else ""),
            ]
        lines += [f"adapter {self.device.context.adapter_name}", *HELP]
        return lines

    def _lens_label(self) -> str:
        """The camera's kind, and its lens where it has one open: aperture radius and focus distance."""
        controller = self.controller
        radius = controller.aperture_radius
        if radius is None or radius == 0.0:
            return type(controller.optics).__name__
        return f"lens {radius:.3g} focus {controller.focus_distance:.4g}"

    def screenshot(self) -> tuple[Path, Path] | None:
        """Save what the window shows (without the overlay) as PNG, and the linear image as EXR."""
        view = self.view
        if view is None:
            return None
        image, image_size = self._picture()
        pixels = self.device.presenter.screenshot(image, image_size, self.canvas.get_physical_size(), self._tone())
        linear = read_texture(self.device.context, image, np.float32, 4, image_size)[:, :, :3].copy()
        png, exr = self.screenshots.save(pixels, linear)
        samples = self._samples_shown()
        shown = self.shown_label() if self.settings.view == View.RADIANCE else self.settings.view.name.lower()
        self.overlay.show_status(f"saved {png.name} and {exr.name} at {samples:.2f} spp ({shown})")
        camera = self.controller.camera()
        moving = self._moving_picture()
        upscale = "" if moving is None else f" upscale {moving.upscale or 1}"
        print(
            f"wgputrace view: saved {png} and {exr}: {samples:.3f} spp at "
            f"{image_size[0]}x{image_size[1]}, camera {' '.join(f'{v:.9g}' for v in camera.position)} "
            f"dir {' '.join(f'{v:.9g}' for v in camera.forward)} speed {self.controller.speed:.9g} (showing {shown})"
            + upscale,
            flush=True,
        )
        return png, exr
