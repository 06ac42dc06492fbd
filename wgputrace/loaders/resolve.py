"""The one way from a scene's name on a command line, in the viewer or in a script to a Scene:
a built-in scene's name, a scene file, or a .py file defining scene().

A spec is a file when it is a Path, or a string with a suffix or a path separator; any other
string names a built-in scene. So a mistyped path reads "no such file", never the list of
built-in scenes, and a mistyped name lists them.
"""

from __future__ import annotations

import os
from numbers import Integral
from pathlib import Path

from ..scene import Scene, Sensor
from ..scene.scene import zero_area
from ..scenes import BUILTIN_SCENES, scene_by_name
from .camera_choice import chosen_camera
from .errors import SceneLoadError
from .framing import LOOK_ALONG_MINUS_Z, LOOK_ALONG_PLUS_Z, framing_camera
from .gltf import read_gltf
from .mesh_files import read_mesh_file
from .obj import read_obj
from .python_scene import read_python_scene

MESH_FORMATS = (".obj", ".gltf", ".glb", ".ply", ".stl")
FORMATS = (*MESH_FORMATS, ".py")
SEPARATORS = tuple(separator for separator in (os.sep, os.altsep, "/") if separator)


def scene_file(spec: str | Path) -> Path | None:
    """The file `spec` names, or None when it names a built-in scene."""
    if isinstance(spec, Path):
        return spec
    if spec in BUILTIN_SCENES or not (Path(spec).suffix or any(separator in spec for separator in SEPARATORS)):
        return None
    return Path(spec)


def load_scene(spec: str | Path, *, camera: Sensor | str | int | None = None) -> Scene:
    """The built-in scene called `spec`, the scene in the file `spec`, or the one a .py file's
    scene() returns; `camera` replaces the scene's camera (for a file without one, its framing): a
    camera, or the name or index of one the file brings (`Scene.cameras`, `chosen_camera`).
    Every failure is a SceneLoadError."""
    path = scene_file(spec)
    if path is None:
        try:
            scene = scene_by_name(str(spec))
        except ValueError as error:
            raise SceneLoadError(None, f"{error}; or give a scene file ({', '.join(FORMATS)})") from None
    else:
        suffix = path.suffix.lower()
        if suffix not in FORMATS:
            found = f"unknown scene format {suffix!r}" if suffix else "no file suffix"
            raise SceneLoadError(path, f"{found}; wgputrace reads {', '.join(FORMATS)}")
        if not path.is_file():
            raise SceneLoadError(path, "no such file")
        scene = read_python_scene(path) if suffix == ".py" else _read_mesh_file(path, suffix, frame=camera is None)
    if isinstance(camera, str | Integral):  # numpy's integers too
        camera = chosen_camera(scene.cameras, camera, path)
    if camera is not None:
        scene.camera = camera
    return scene


def _read_mesh_file(path: Path, suffix: str, *, frame: bool) -> Scene:
    """The scene in a mesh file with the file's lights and cameras, seen from the first of them; for
    a file without a camera (if `frame`), from one framing it all."""
    cameras, lights, instances, forward = [], [], [], LOOK_ALONG_PLUS_Z
    if suffix == ".obj":
        shapes = read_obj(path)
    elif suffix in (".gltf", ".glb"):
        shapes, cameras, lights, instances = read_gltf(path)
        forward = LOOK_ALONG_MINUS_Z
    else:
        shapes = read_mesh_file(path)
    scene = Scene([shape for shape in shapes if shape.triangle_count], cameras=cameras, instances=instances)
    scene.add_light(*lights)
    if not scene.shapes:
        raise SceneLoadError(path, "holds no triangles")
    if all(zero_area(shape.world_vertices).all() for shape in scene.shapes):
        raise SceneLoadError(path, f"all {scene.triangle_count:,} triangles have zero area")
    if cameras:
        scene.camera = cameras[0][1]
    elif frame:
        try:
            scene.camera = framing_camera(scene, forward)
        except ValueError as error:
            raise SceneLoadError(path, f"cannot frame the scene automatically: {error}") from None
    return scene
