"""Scenes written in Python: a .py file defining `scene() -> wgputrace.Scene`, run as a script.

Whatever the file does wrong is a SceneLoadError naming the file, the line that failed (the
innermost frame inside the file) and the exception, so the viewer can show it and keep running.
"""

from __future__ import annotations

import traceback
from pathlib import Path

from ..scene import Scene
from .errors import SceneLoadError

SCENE_FUNCTION = "scene"


def _failing_line(error: BaseException, path: Path) -> int | None:
    if isinstance(error, SyntaxError) and error.filename == str(path):
        return error.lineno
    frames = [frame for frame in traceback.extract_tb(error.__traceback__) if frame.filename == str(path)]
    return frames[-1].lineno if frames else None


def read_python_scene(path: Path) -> Scene:
    """The scene `path`'s scene() returns, checked the way the renderer will check it."""
    try:
        source = path.read_text()
    except OSError as error:
        raise SceneLoadError(path, f"cannot read the file: {error.strerror or error}") from None
    namespace: dict = {"__file__": str(path), "__name__": "wgputrace_scene_file"}
    try:
        exec(compile(source, str(path), "exec"), namespace)
        function = namespace.get(SCENE_FUNCTION)
        if not callable(function):
            raise SceneLoadError(path, f"defines no function {SCENE_FUNCTION}() returning a wgputrace.Scene")
        scene = function()
        if not isinstance(scene, Scene):
            raise SceneLoadError(path, f"{SCENE_FUNCTION}() returned {type(scene).__name__}, not a wgputrace.Scene")
        scene.arrays()  # an empty or inconsistent scene fails here, with the scene's own message
    except SceneLoadError:
        raise
    except Exception as error:  # a scene file is arbitrary code: any failure is the file's
        raise SceneLoadError(path, f"{type(error).__name__}: {error}", _failing_line(error, path)) from None
    return scene
