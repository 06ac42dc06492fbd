"""Scene description in pure numpy (never imports wgpu): shapes, materials, camera."""

from .camera import Camera
from .cornell import cornell_box
from .materials import Diffuse, Emitter, Glass, Glossy, Material, MaterialError, MaterialKind
from .scene import DegenerateTrianglesWarning, Scene, SceneError, TriangleArrays
from .shapes import Shape, make_box, make_icosphere, make_plane

__all__ = [
    "Camera",
    "DegenerateTrianglesWarning",
    "Diffuse",
    "Emitter",
    "Glass",
    "Glossy",
    "Material",
    "MaterialError",
    "MaterialKind",
    "Scene",
    "SceneError",
    "Shape",
    "TriangleArrays",
    "cornell_box",
    "make_box",
    "make_icosphere",
    "make_plane",
]
