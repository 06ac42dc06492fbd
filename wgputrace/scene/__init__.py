"""Scene description in pure numpy (never imports wgpu): shapes, materials, lights, cameras."""

from . import cameras, lights, materials
from .cameras import *  # noqa: F403 (the base, its error and every camera kind, by module discovery)
from .cornell import cornell_box
from .errors import SceneError
from .instances import Instance
from .lights import *  # noqa: F403 (the base, its error and every light kind, by module discovery)
from .materials import *  # noqa: F403 (the base, its error and every material kind, by module discovery)
from .scene import DegenerateTrianglesWarning, Scene, TriangleArrays
from .shapes import Shape, make_box, make_icosphere, make_plane, model_matrix
from .texture import Texture, TextureTransform

__all__ = [
    "DegenerateTrianglesWarning",
    "Instance",
    "Scene",
    "SceneError",
    "Shape",
    "Texture",
    "TextureTransform",
    "TriangleArrays",
    "cornell_box",
    "make_box",
    "make_icosphere",
    "make_plane",
    "model_matrix",
    *cameras.__all__,
    *lights.__all__,
    *materials.__all__,
]
