"""wgputrace: a Monte Carlo path tracer for Python on WGSL compute shaders (wgpu-py).

import wgputrace as wt
scene = wt.default_scene()
img = wt.render(scene, spp=64, width=512, height=512, seed=1, max_depth=9)
wt.save_image("out.exr", img)
wt.save_image("out.png", img, tonemap="agx", exposure=0.5)  # the picture: a tone curve, stops of exposure
"""

from importlib.metadata import version

from . import cluster  # rendering on a Ray cluster; Ray itself is imported only when a cluster call runs
from .denoise import DenoiserMissing, denoise
from .gpu.device import DeviceLimitError, GpuFailure
from .image_io import load_image, load_layers, save_image, tonemap
from .loaders import SceneLoadError, SceneLoadWarning, load_scene
from .provenance import read_metadata
from .render import UNLIMITED_DEPTH, Renderer, render
from .scene import Instance, Scene, Shape, Texture, TextureTransform, make_box, make_icosphere, make_plane, model_matrix
from .scene.cameras import KINDS as CAMERA_KINDS
from .scene.cameras import Sensor
from .scene.lights import KINDS as LIGHT_KINDS
from .scene.lights.environment import Environment
from .scene.materials import KINDS
from .scenes import default_scene

# every material kind (Diffuse, Emitter, Glass, Glossy, and any module added to wgputrace.scene.materials)
globals().update(KINDS)
# every camera kind (Camera, ThinLensCamera, OrthographicCamera, EquirectangularCamera, and any module added to
# wgputrace.scene.cameras)
globals().update(CAMERA_KINDS)
# every light kind (DirectionalLight, PointLight, SpotLight, Sun, and any module added to wgputrace.scene.lights)
globals().update(LIGHT_KINDS)

# one source of the version: pyproject.toml, as installed
__version__ = version("wgputrace")

__all__ = [
    "UNLIMITED_DEPTH",
    "DenoiserMissing",
    "DeviceLimitError",
    "Environment",
    "GpuFailure",
    "Instance",
    "Renderer",
    "Scene",
    "Sensor",
    "SceneLoadError",
    "SceneLoadWarning",
    "Shape",
    "Texture",
    "TextureTransform",
    "cluster",
    "default_scene",
    "denoise",
    "load_image",
    "load_layers",
    "load_scene",
    "make_box",
    "make_icosphere",
    "make_plane",
    "model_matrix",
    "read_metadata",
    "render",
    "save_image",
    "tonemap",
    *CAMERA_KINDS,
    *KINDS,
    *LIGHT_KINDS,
]
