"""Scenes for the viewer: a built-in name, a scene file wgputrace.loaders reads (OBJ, glTF, PLY,
STL), or a Python file defining `scene() -> wgputrace.Scene`.

A file that fails to load raises SceneLoadError naming the file, the line and the problem, so the
viewer can show it and keep the scene it had. The viewer reloads a file when it changes.
"""

from __future__ import annotations

import traceback
from pathlib import Path

from ..scene import Scene
from ..scenes import BUILTIN_SCENES, scene_by_name

SCENE_FUNCTION = "scene"


class SceneLoadError(RuntimeError):
    """The scene could not be loaded; the message names the file and line."""


def is_scene_file(spec: str) -> bool:
    return spec not in BUILTIN_SCENES and Path(spec).suffix != ""


def _where(error: BaseException, path: Path) -> str:
    """'file:line' of the innermost frame inside the scene file, else of the file itself."""
    if isinstance(error, SyntaxError) and error.lineno is not None:
        return f"{path}:{error.lineno}"
    frames = [frame for frame in traceback.extract_tb(error.__traceback__) if Path(frame.filename) == path]
    return f"{path}:{frames[-1].lineno}" if frames else str(path)


def load_scene(spec: str) -> Scene:
    """The built-in scene called `spec`, the scene in a file, or the one a .py file's `scene()` returns."""
    if not is_scene_file(spec):
        try:
            return scene_by_name(spec)
        except ValueError as error:
            raise SceneLoadError(f"{error}; or give a scene file") from None
    path = Path(spec).resolve()
    if path.suffix != ".py":
        from .. import loaders

        try:
            return loaders.load_scene(path)
        except Exception as error:  # the loaders' errors name file and line; anything else is shown as it is
            raise SceneLoadError(f"{type(error).__name__}: {error}") from None
    try:
        source = path.read_text()
    except OSError as error:
        raise SceneLoadError(f"{path}: cannot read the scene file: {error.strerror}") from None
    namespace: dict = {"__file__": str(path), "__name__": "wgputrace_scene_file"}
    try:
        exec(compile(source, str(path), "exec"), namespace)
        function = namespace.get(SCENE_FUNCTION)
        if not callable(function):
            raise SceneLoadError(f"{path}: defines no function {SCENE_FUNCTION}() returning a wgputrace.Scene")
        scene = function()
        if not isinstance(scene, Scene):
            raise SceneLoadError(f"{path}: {SCENE_FUNCTION}() returned {type(scene).__name__}, not a wgputrace.Scene")
        scene.arrays()  # an empty or inconsistent scene fails here, with the scene's own message
    except SceneLoadError:
        raise
    except Exception as error:  # whatever the file does wrong, the viewer keeps running
        raise SceneLoadError(f"{_where(error, path)}: {type(error).__name__}: {error}") from None
    return scene


def modified_time(spec: str) -> float | None:
    """When a scene file last changed (None for built-in scenes and unreadable files)."""
    if not is_scene_file(spec):
        return None
    try:
        return Path(spec).stat().st_mtime
    except OSError:
        return None
