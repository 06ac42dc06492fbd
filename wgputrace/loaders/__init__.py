"""Scenes from files: OBJ (+MTL), glTF/GLB, PLY and STL, onto wgputrace's shapes, materials and camera.

`load_scene(path)` reads the file by its extension, maps its materials (the tables are in obj.py
and gltf.py, and in the README), takes the file's camera if it has one and otherwise frames the
whole scene (framing.py). Every problem with the file is a SceneLoadError naming the file, the line
for text formats or the JSON path for glTF, and what is wrong; repairs and skipped parts are
SceneLoadWarnings. Zero-area triangles stay in the scene and are dropped, with a count, when it is
rendered (DegenerateTrianglesWarning).
"""

from __future__ import annotations

from pathlib import Path

from ..scene import Camera, Scene
from ..scene.scene import zero_area
from .errors import SceneLoadError, SceneLoadWarning
from .framing import LOOK_ALONG_MINUS_Z, LOOK_ALONG_PLUS_Z, framing_camera
from .gltf import read_gltf
from .mesh_files import read_mesh_file
from .obj import read_obj

FORMATS = (".obj", ".gltf", ".glb", ".ply", ".stl")


def load_scene(path: str | Path, *, camera: Camera | None = None) -> Scene:
    """The scene in `path`; `camera` replaces the file's camera (or the automatic framing)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise SceneLoadError(path, f"unknown scene format {suffix!r}; wgputrace reads {', '.join(FORMATS)}")
    if not path.is_file():
        raise SceneLoadError(path, "no such file")
    file_camera, forward = None, LOOK_ALONG_PLUS_Z
    if suffix == ".obj":
        shapes = read_obj(path)
    elif suffix in (".gltf", ".glb"):
        shapes, file_camera = read_gltf(path)
        forward = LOOK_ALONG_MINUS_Z
    else:
        shapes = read_mesh_file(path)
    scene = Scene([shape for shape in shapes if shape.triangle_count])
    if not scene.shapes:
        raise SceneLoadError(path, "holds no triangles")
    if all(zero_area(shape.world_vertices).all() for shape in scene.shapes):
        raise SceneLoadError(path, f"all {scene.triangle_count:,} triangles have zero area")
    if camera is None and file_camera is None:
        try:
            file_camera = framing_camera(scene, forward)
        except ValueError as error:
            raise SceneLoadError(path, f"cannot frame the scene automatically: {error}") from None
    scene.camera = camera or file_camera
    return scene


__all__ = ["FORMATS", "SceneLoadError", "SceneLoadWarning", "load_scene"]
