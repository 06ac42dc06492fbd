"""A scene's own cameras (`Scene.cameras`, the ones its file brings): one chosen by name or index, as
`load_scene(..., camera=...)` and `--camera NAME|INDEX` choose it, and the list `wgputrace info
model.glb` prints. A name is matched first, so a camera called "2" is found by that name; a string
of digits that names no camera is an index."""

from __future__ import annotations

from numbers import Integral
from pathlib import Path

from ..scene import Sensor
from .errors import SceneLoadError

# An error lists at most this many cameras, so that it stays one readable line.
LISTED_IN_ERRORS = 12


def chosen_camera(cameras: list[tuple[str, Sensor]], choice: str | Integral, path: Path | None) -> Sensor:
    """The camera of `cameras` called `choice`, or at index `choice`; a SceneLoadError naming
    `path` and the cameras there are for one that is not there, or a name that several share."""
    if isinstance(choice, str):
        named = [index for index, (name, _) in enumerate(cameras) if name == choice]
        if len(named) > 1:
            raise SceneLoadError(
                path, f"{len(named)} cameras are called {choice!r:.40} (indices {named}): give its index"
            )
        if named:
            return cameras[named[0]][1]
    index = int(choice) if isinstance(choice, str) and choice.isascii() and choice.isdigit() else choice
    if isinstance(index, Integral) and not isinstance(index, bool) and 0 <= index < len(cameras):
        return cameras[int(index)][1]
    raise SceneLoadError(path, f"no camera {choice!r:.40}; {_listed(cameras)}")


def _listed(cameras: list[tuple[str, Sensor]]) -> str:
    if not cameras:
        return "the scene brings no cameras of its own"
    shown = ", ".join(f"{index} {name!r}" for index, (name, _) in enumerate(cameras[:LISTED_IN_ERRORS]))
    more = f" and {len(cameras) - LISTED_IN_ERRORS} more" if len(cameras) > LISTED_IN_ERRORS else ""
    return f"its cameras: {shown}{more}"


def camera_lines(cameras: list[tuple[str, Sensor]]) -> list[str]:
    """One line per camera: its index, name, kind, pose and parameters."""
    return [f"{index:>3}  {name!r}  {camera.description()}" for index, (name, camera) in enumerate(cameras)]
