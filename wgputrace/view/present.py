"""Presenting a resolved image to a window's texture (or an offscreen one, for screenshots): scaled
to the target, exposure (set, or measured by the auto-exposure pass), a tone curve, sRGB, the text
overlay, and BVH box edges drawn as lines. All on the GPU: drawing reads nothing back."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..gpu.buffers import read_buffer, storage_buffer, uniform_buffer, write_buffer
from ..gpu.device import GpuContext
from ..gpu.graphics import RenderKernel, read_texture, rgba8_texture, target_texture, write_rgba8
from ..image_io import DEFAULT_TONEMAP, TONEMAP_OPERATORS, check_tonemap
from ..kernels.compile import compute_kernel
from ..render.display_constants import GENERATED_DISPLAY_CONSTANTS, display_constants
from ..scene import Sensor
from .layout import (
    BOX_LINES_GROUP,
    BOX_LINES_PARAMS,
    EXPOSURE_GROUP,
    EXPOSURE_PARAMS,
    GENERATED_VIEW_STRUCTS,
    PRESENT_GROUP,
    PRESENT_PARAMS,
    generated_view_structs,
)

# trac0r drew its boxes in yellow.
BOX_COLOR = (1.0, 0.85, 0.0, 1.0)
# Box edges closer than NEAR_FRACTION or farther than FAR_FACTOR times the scene's size from the
# camera are clipped (the depth range of the line projection).
NEAR_FRACTION = 1e-4
FAR_FACTOR = 1e3
# Auto-exposure follows the picture's log-average luminance with this time constant: a new scene
# or view settles in about three of them, and a frame's noise hardly moves it.
AUTO_EXPOSURE_SECONDS = 0.5
# The auto-exposure pass runs one workgroup of this many invocations (view/exposure.wgsl).
EXPOSURE_WORKGROUP = 256


@dataclass(frozen=True)
class Tone:
    """How radiance is shown: times 2^`ev`, and by the auto-exposure's factor where `automatic`
    (MIDDLE_GREY over the measured log average, `ev` then a compensation), through the tone curve
    `operator` (`image_io.tone_curve`)."""

    operator: str = DEFAULT_TONEMAP
    ev: float = 0.0
    automatic: bool = False

    def __post_init__(self) -> None:
        check_tonemap(self.operator)
        if not math.isfinite(self.ev):
            raise ValueError(f"exposure must be a finite number of stops, got {self.ev!r}")


def camera_clip_matrix(camera: Sensor, width: int, height: int, scene_size: float) -> np.ndarray | None:
    """4x4 world-to-clip matrix that puts a point where the path tracer's camera ray through it
    lands (`Sensor.clip_matrix`), clipping at NEAR_FRACTION and FAR_FACTOR of `scene_size`; None
    for a camera no matrix projects for (the equirectangular one)."""
    return camera.clip_matrix(width, height, NEAR_FRACTION * scene_size, FAR_FACTOR * scene_size)


class Presenter:
    """Draws to textures of `target_format`; encodes sRGB itself when the format does not."""

    def __init__(self, context: GpuContext, target_format: str) -> None:
        self.context, self.target_format = context, target_format
        generated = {GENERATED_VIEW_STRUCTS: generated_view_structs(), GENERATED_DISPLAY_CONSTANTS: display_constants()}
        encode = not target_format.endswith("-srgb")
        self._image_kernel = RenderKernel(
            context,
            "view/present.wgsl",
            target_format,
            (PRESENT_GROUP,),
            generated=generated,
            constants={"ENCODE_SRGB": encode},
        )
        self._lines_kernel = RenderKernel(
            context, "view/bvh_lines.wgsl", target_format, (BOX_LINES_GROUP,), generated=generated, topology="line-list"
        )
        self._params = uniform_buffer(context, "present params", PRESENT_PARAMS.zeros(1))
        self._exposure_kernel = compute_kernel(
            context,
            "view/exposure.wgsl",
            (EXPOSURE_GROUP,),
            generated=generated,
            workgroup_size=(EXPOSURE_WORKGROUP, 1),
        )
        self._exposure_params = uniform_buffer(context, "exposure params", EXPOSURE_PARAMS.zeros(1))
        # the smoothed log-average luminance (EXPOSURE_STATE): unmeasured until the first pass
        self._exposure_state = storage_buffer(context, "exposure state", np.zeros(4, np.float32), read_back=True)
        self._lines_params = uniform_buffer(context, "box lines params", BOX_LINES_PARAMS.zeros(1))
        self._overlay = rgba8_texture(context, "overlay", 1, 1)
        self._overlay_position = (0, 0)
        self._lines: tuple[object, int] | None = None
        self._lines_group = None

    def set_overlay(self, pixels: np.ndarray | None, position: tuple[int, int] = (0, 0)) -> None:
        """Show (height, width, 4) uint8 RGBA pixels (straight alpha) at `position` from the
        target's top-left corner; None hides the overlay."""
        if pixels is None:
            self._overlay_position = None
            return
        height, width = pixels.shape[:2]
        if tuple(self._overlay.size[:2]) != (width, height):
            self._overlay = rgba8_texture(self.context, "overlay", width, height)
        write_rgba8(self.context, self._overlay, pixels)
        self._overlay_position = position

    def set_box_lines(self, endpoints: np.ndarray | None) -> None:
        """Draw the (n, 2, 3) world-space segments over the image from now on; None stops."""
        if endpoints is None or len(endpoints) == 0:
            self._lines, self._lines_group = None, None
            return
        points = np.zeros((len(endpoints) * 2, 4), np.float32)
        points[:, :3] = endpoints.reshape(-1, 3)
        buffer = storage_buffer(self.context, "box line endpoints", points)
        self._lines = (buffer, len(points))
        self._lines_group = self._lines_kernel.bind("box_lines", params=self._lines_params, endpoints=buffer)

    def set_camera(self, camera: Sensor, width: int, height: int, scene_size: float) -> None:
        """The camera (and full image size) the box lines are projected with; a camera that no
        matrix projects for hides them (every point at clip w = -1, which the GPU clips away)."""
        record = BOX_LINES_PARAMS.zeros(1)
        matrix = camera_clip_matrix(camera, width, height, scene_size)
        if matrix is None:
            record["row_w"] = (0.0, 0.0, 0.0, -1.0)
        else:
            record["row_x"], record["row_y"], record["row_z"], record["row_w"] = matrix
        record["color"] = BOX_COLOR
        write_buffer(self.context, self._lines_params, 0, record)

    def measure_exposure(self, image, image_size: tuple[int, int], seconds: float, *, restart: bool = False) -> None:
        """Blend the log-average luminance of `image` (image_size pixels from its top-left corner)
        into the auto-exposure's state, as much as `seconds` since the last measurement weigh with
        AUTO_EXPOSURE_SECONDS; `restart` takes it whole (auto-exposure switched on)."""
        record = EXPOSURE_PARAMS.zeros(1)
        record["width"], record["height"] = image_size
        record["blend"] = 1.0 - math.exp(-max(seconds, 0.0) / AUTO_EXPOSURE_SECONDS)
        record["restart"] = int(restart)
        write_buffer(self.context, self._exposure_params, 0, record)
        group = self._exposure_kernel.bind(
            "exposure", params=self._exposure_params, image=image, exposure_state=self._exposure_state
        )
        self._exposure_kernel.dispatch((EXPOSURE_WORKGROUP,), {"exposure": group})

    def measured_log_average(self) -> float | None:
        """The auto-exposure's smoothed log-average luminance (natural log), None before any
        measurement. Reads the GPU's state back: for tests, not for every frame."""
        state = read_buffer(self.context, self._exposure_state, np.float32, 4)
        return float(state[0]) if state[1] else None

    def draw(self, target, image, image_size: tuple[int, int], tone: Tone, *, overlay: bool = True) -> None:
        """Draw `image` (the texture Display.render returned, image_size pixels from its top-left
        corner) to the texture `target`, shown as `tone` says."""
        width, height = target.size[0], target.size[1]
        params = PRESENT_PARAMS.zeros(1)
        params["image_width"], params["image_height"] = image_size
        params["target_width"], params["target_height"] = width, height
        show_overlay = overlay and self._overlay_position is not None
        if show_overlay:
            params["overlay_x"], params["overlay_y"] = self._overlay_position
        params["overlay_visible"] = int(show_overlay)
        params["exposure"] = 2.0**tone.ev
        params["tonemap"] = TONEMAP_OPERATORS.index(tone.operator)
        params["auto_exposure"] = int(tone.automatic)
        write_buffer(self.context, self._params, 0, params)
        group = self._image_kernel.bind(
            "present", params=self._params, image=image, overlay=self._overlay, exposure_state=self._exposure_state
        )
        encoder = self.context.device.create_command_encoder()
        render = encoder.begin_render_pass(
            color_attachments=[
                {"view": target.create_view(), "load_op": "clear", "store_op": "store", "clear_value": (0, 0, 0, 1)}
            ]
        )
        self._image_kernel.set_bind_groups(render, {"present": group})
        render.draw(3)
        if self._lines is not None:
            self._lines_kernel.set_bind_groups(render, {"box_lines": self._lines_group})
            render.draw(self._lines[1])
        render.end()
        self.context.submit(encoder, "presenting the picture")

    def screenshot(self, image, image_size: tuple[int, int], size: tuple[int, int], tone: Tone) -> np.ndarray:
        """What `draw` shows on a target of `size`, without the overlay, as (height, width, 3) uint8 sRGB."""
        texture = target_texture(self.context, "screenshot", size[0], size[1], self.target_format)
        self.draw(texture, image, image_size, tone, overlay=False)
        pixels = read_texture(self.context, texture, np.uint8, 4)
        if self.target_format.startswith("bgra"):
            pixels = pixels[:, :, [2, 1, 0, 3]]
        return pixels[:, :, :3]
