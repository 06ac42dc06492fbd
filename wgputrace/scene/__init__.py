"""Scene description in pure numpy (never imports wgpu): shapes, materials, camera."""

from .camera import Camera
from .cornell import cornell_box
from .errors import SceneError
from .materials import Diffuse, Emitter, Glass, Glossy, Material, MaterialError, MaterialKind
from .scene import DegenerateTrianglesWarning, Scene, TriangleArrays
from .shapes import Shape, make_box, make_icosphere, make_plane, model_matrix

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
    "model_matrix",
]
