"""The base of every camera kind (`Sensor`, Mitsuba 3's name for what a camera is) and the registry
of those kinds.

A camera kind is one class in one module of this package plus its WGSL file under shaders/camera/,
and nothing else: like a material or a light kind (`Kind`), the class is the whole descriptor.

| what                                      | on the class        | driven from it                                  |
|-------------------------------------------|---------------------|-------------------------------------------------|
| the id its kernels are compiled for       | `kind`              | `SceneFeatures.camera`, `camera_hook`           |
| parameters and their checks               | dataclass fields, `checked_lens` | editing re-checks (`__setattr__`)   |
| its part of the FRAME record              | `fill_frame`        | `Renderer.frame_record`                         |
| its rays, and how bdpt connects to it     | `shader`            | `camera_hook` (the WGSL contract: `camera/camera.wgsl`) |
| the images it is meant for                | `check_image`       | `Renderer` warns (CameraWarning)                |
| where a point lands on its image          | `clip_matrix`       | the viewer's BVH box lines                      |
| how it takes in a whole scene             | `framed`            | the viewer's F key                              |
| its Mitsuba 3 sensor                      | `mitsuba_sensor`    | `mitsuba_scene`                                 |

Every kind stands at `position` and looks along `forward` (normalised when set), `up` giving the
image's up: right = cross(forward, up), row 0 of an image is its top. Assigning a parameter re-runs
the camera's checks (CameraError names the camera kind, the parameter and the value, and leaves the
camera as it was) and bumps `version`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import SceneError
from ..registry import Kind, KindRegistry, ParameterError

# Below this |cross(forward, up)| the up vector gives no usable "right" direction.
_PARALLEL_LIMIT = 1e-6


class CameraError(ParameterError, SceneError):
    """A camera parameter is out of its documented range; `parameter` names it. A SceneError too, as
    the checks of the camera were before there were camera kinds."""


class CameraWarning(UserWarning):
    """An image does not suit the camera that renders it (an equirectangular image that is not 2:1)."""


def _check_kind(cls: type[Sensor], where: str) -> None:
    if not isinstance(cls.shader, str) or not cls.shader.endswith(".wgsl"):
        raise TypeError(f"{where}: shader must name its WGSL file under shaders/, got {cls.shader!r}")


CAMERA_KINDS = KindRegistry("camera", _check_kind)
# every registered camera kind in id order, and the class registered for a kind
camera_classes = CAMERA_KINDS.classes
camera_class = CAMERA_KINDS.lookup


@dataclass
class Sensor(Kind):
    """Where a camera stands (`position`) and which way it looks (`forward`, normalised when set;
    `up` the image's up); each kind adds how it projects."""

    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    forward: tuple[float, float, float] = (0.0, 0.0, 1.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)

    registry: ClassVar[KindRegistry] = CAMERA_KINDS
    parameter_error: ClassVar[type[ParameterError]] = CameraError
    # the id its kernels are compiled for (SceneFeatures.camera)
    kind: ClassVar[int]
    # its WGSL file under shaders/
    shader: ClassVar[str]

    @property
    def label(self) -> str:
        """How errors name the camera: its kind's class name."""
        return type(self).__name__

    def checked_parameters(self) -> dict[str, object]:
        checked = self.checked_lens()
        checked.update(self.checked_pose())
        return checked

    def checked_lens(self) -> dict[str, object]:
        """The kind's parameters besides its pose (field of view, aperture, extent), checked and
        normalised before the pose."""
        return {}

    def checked_pose(self) -> dict[str, object]:
        """position, forward and up: 3 finite numbers each, forward not zero (and normalised), up
        not parallel to it."""
        position, forward, up = (self._vector(name) for name in ("position", "forward", "up"))
        length = np.linalg.norm(forward)
        if length == 0.0:
            raise CameraError(f"{self.label}: forward is the zero vector", "forward")
        if not np.isfinite(length):
            raise CameraError(f"{self.label}: forward {forward.tolist()} is too long to normalize", "forward")
        forward = forward / length
        if np.linalg.norm(np.cross(forward, up)) < _PARALLEL_LIMIT * max(np.linalg.norm(up), 1.0):
            raise CameraError(f"{self.label}: up {up.tolist()} is parallel to forward {forward.tolist()}", "up")
        return {"position": tuple(position.tolist()), "forward": tuple(forward.tolist()), "up": tuple(up.tolist())}

    def _vector(self, parameter: str) -> np.ndarray:
        value = getattr(self, parameter)
        try:
            vector = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise CameraError(f"{self.label}: {parameter} must be 3 finite numbers, got {value!r}", parameter) from None
        if vector.shape != (3,) or not np.all(np.isfinite(vector)):
            raise CameraError(f"{self.label}: {parameter} must be 3 finite numbers, got {vector.tolist()}", parameter)
        return vector

    def check_length(self, parameter: str, value, *, zero: bool) -> float:
        """A finite length: above 0, or from 0 on where `zero`."""
        bound = ">= 0" if zero else "> 0"
        message = f"{self.label}: {parameter} must be a finite number {bound}, got {value!r}"
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise CameraError(message, parameter) from None
        if not math.isfinite(number) or number < 0.0 or (number == 0.0 and not zero):
            raise CameraError(message, parameter)
        return number

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit (right, up, forward) of the image: right = cross(forward, up)."""
        forward = np.asarray(self.forward)
        right = np.cross(forward, self.up)
        right /= np.linalg.norm(right)
        return right, np.cross(right, forward), forward

    def posed(self, position, forward, up) -> Sensor:
        """The same camera (kind and parameters) moved to `position`, looking along `forward`."""
        return dataclasses.replace(self, position=tuple(position), forward=tuple(forward), up=tuple(up))

    def fill_frame(self, record: np.ndarray, width: int, height: int) -> None:
        """Write the camera's fields of one FRAME record for an image of `width` x `height`, as its
        WGSL reads them: camera_position, camera_right, camera_up, camera_forward, and the lens."""
        raise NotImplementedError

    def check_image(self, width: int, height: int) -> None:
        """Warn (CameraWarning) where an image of `width` x `height` does not suit the camera."""

    def clip_matrix(self, width: int, height: int, near: float, far: float) -> np.ndarray | None:
        """4x4 world-to-clip matrix that puts a point where the camera's ray through it lands (clip
        x, y in [-1, 1], y up; depth in [0, 1] from `near` to `far`); None where no matrix can."""
        raise NotImplementedError

    def translated(self, matrix: np.ndarray) -> np.ndarray:
        """A clip matrix whose rows act on the offset from `position`, with the translation folded in."""
        matrix[:, 3] -= matrix[:, :3] @ np.asarray(self.position)
        return matrix

    def framed(self, radius: float, aspect: float) -> tuple[float, Sensor]:
        """How far behind a sphere's centre, along forward, the camera stands to see all of the
        sphere of `radius` on an image of width / height = `aspect`, and the camera with the
        parameters that takes (an orthographic view widened to it)."""
        raise NotImplementedError

    def mitsuba_sensor(self, width: int, height: int) -> dict | None:
        """The Mitsuba 3 sensor dict without its film, sampler and clip planes; None where no
        Mitsuba plugin is this camera. Its transform is given as {"look_at": {"origin", "target",
        "up"}} and optionally "scale" (x, y, z), which the exporter turns into Mitsuba's
        `ScalarTransform4f().look_at(...) @ scale(...)`; `width` x `height` is the film's size."""
        raise NotImplementedError

    def description(self) -> str:
        """The camera in one line, for the provenance of an image: its kind and parameters."""
        values = ", ".join(f"{name} {_number(getattr(self, name))}" for name in self.parameter_names())
        return f"{type(self).__name__}: {values}"

    def look_at(self) -> dict:
        """The pose as the {"look_at": ...} of `mitsuba_sensor` (Mitsuba's look_at gives image right =
        cross(forward, up), as ours)."""
        position = np.asarray(self.position)
        return {
            "origin": position.tolist(),
            "target": (position + np.asarray(self.forward)).tolist(),
            "up": list(self.up),
        }


def _number(value) -> str:
    """A parameter as provenance writes it: numbers with %g, vectors as a,b,c."""
    if isinstance(value, tuple):
        return ",".join(f"{v:.9g}" for v in value)
    return f"{value:.9g}" if isinstance(value, float | int) else str(value)
