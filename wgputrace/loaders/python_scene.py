"""Scenes written in Python: a .py file defining `scene() -> wgputrace.Scene`, run as a script; an
animation defines `scene(frame)` instead, and is read one frame at a time (a still of it is frame 0).

Whatever the file does wrong is a SceneLoadError naming the file, the line that failed (the
innermost frame inside the file) and the exception, so the viewer can show it and keep running.
The source can come as text (`scene_from_source`): a cluster's workers build an animation's frames
from the text the driver sent them, on machines that may not have the file.
"""

from __future__ import annotations

import inspect
import traceback
from collections.abc import Callable
from pathlib import Path

from ..scene import Scene
from .errors import SceneLoadError

SCENE_FUNCTION = "scene"
# the frame a file defining scene(frame) renders as a still
STILL_FRAME = 0


def _failing_line(error: BaseException, path: Path) -> int | None:
    if isinstance(error, SyntaxError) and error.filename == str(path):
        return error.lineno
    frames = [frame for frame in traceback.extract_tb(error.__traceback__) if frame.filename == str(path)]
    return frames[-1].lineno if frames else None


def read_source(path: Path) -> str:
    """The text of the scene file `path`, or a SceneLoadError saying why it cannot be read."""
    try:
        return path.read_text()
    except OSError as error:
        raise SceneLoadError(path, f"cannot read the file: {error.strerror or error}") from None


def read_python_scene(path: Path, frame: int | None = None) -> Scene:
    """The scene `path`'s scene() returns (or scene(frame), for an animation), checked the way the
    renderer will check it."""
    return scene_from_source(read_source(path), path, frame)


def takes_frame(function: Callable) -> bool:
    """Whether a file's scene function is an animation's, scene(frame)."""
    try:
        parameters = inspect.signature(function).parameters.values()
    except (TypeError, ValueError):  # a callable without a signature Python can read: a still
        return False
    return any(
        parameter.kind in (parameter.POSITIONAL_ONLY, parameter.POSITIONAL_OR_KEYWORD) for parameter in parameters
    )


def scene_from_source(source: str, path: Path, frame: int | None = None) -> Scene:
    """The scene the Python `source` of the file `path` defines: scene() for a still; scene(frame)
    for an animation (frame STILL_FRAME when `frame` is None). Asking a still for a frame is a
    SceneLoadError: it has none to give."""
    namespace: dict = {"__file__": str(path), "__name__": "wgputrace_scene_file"}
    try:
        exec(compile(source, str(path), "exec"), namespace)
        function = namespace.get(SCENE_FUNCTION)
        if not callable(function):
            raise SceneLoadError(path, f"defines no function {SCENE_FUNCTION}() returning a wgputrace.Scene")
        if takes_frame(function):
            scene = function(STILL_FRAME if frame is None else frame)
        elif frame is None:
            scene = function()
        else:
            raise SceneLoadError(
                path,
                f"defines {SCENE_FUNCTION}() without a frame parameter; an animation defines {SCENE_FUNCTION}(frame)",
            )
        if not isinstance(scene, Scene):
            raise SceneLoadError(path, f"{SCENE_FUNCTION}() returned {type(scene).__name__}, not a wgputrace.Scene")
        scene.arrays()  # an empty or inconsistent scene fails here, with the scene's own message
    except SceneLoadError:
        raise
    except Exception as error:  # a scene file is arbitrary code: any failure is the file's
        raise SceneLoadError(path, f"{type(error).__name__}: {error}", _failing_line(error, path)) from None
    return scene
