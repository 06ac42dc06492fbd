"""Scenes by name or from files: `load_scene(spec)` takes a built-in scene's name, a scene file
(OBJ (+MTL), glTF/GLB, PLY, STL) or a .py file defining scene() (`scene_file` tells them apart).

Scene files are read by their extension onto wgputrace's shapes, materials and camera (material
tables: the OBJ reader's `_mapping`, `GltfMaterials._mapped`); a file without a camera is framed
whole (`framing_camera`). Every problem is a SceneLoadError naming the file, the line for text
formats or the JSON path for glTF, and what is wrong; repairs and skipped parts are
SceneLoadWarnings. Zero-area triangles stay in the scene and are dropped, with a count, when it
is rendered (DegenerateTrianglesWarning).
"""

from __future__ import annotations

from .errors import SceneLoadError, SceneLoadWarning
from .resolve import FORMATS, load_scene, scene_file

__all__ = ["FORMATS", "SceneLoadError", "SceneLoadWarning", "load_scene", "scene_file"]
