"""Scene description in pure numpy (never imports wgpu): shapes, materials, camera."""

from . import materials
from .camera import Camera
from .cornell import cornell_box
from .errors import SceneError
from .materials import *  # noqa: F403 (the base, its error and every material kind, by module discovery)
from .scene import DegenerateTrianglesWarning, Scene, TriangleArrays
from .shapes import Shape, make_box, make_icosphere, make_plane, model_matrix

__all__ = [
    "Camera",
    "DegenerateTrianglesWarning",
    "Scene",
    "SceneError",
    "Shape",
    "TriangleArrays",
    "cornell_box",
    "make_box",
    "make_icosphere",
    "make_plane",
    "model_matrix",
    *materials.__all__,
]
