"""A camera for files that bring none: the whole scene in view, seen from a fixed side.

Rule: the camera looks at the centre of the scene's bounding box along `forward` (+y up) with a
vertical field of view of FRAMING_VFOV_DEGREES, from where the bounding sphere (centre of the box,
radius half its diagonal) just fills the vertical field of view. A wider-than-tall image therefore
shows all of it; a taller-than-wide one may crop the sides. glTF assets face +z (the glTF
specification's convention), so for them the camera stands on the +z side looking along -z; the
other formats have no convention, and the camera takes the project's (the Cornell box's): on the
-z side, looking along +z.
"""

from __future__ import annotations

import math

import numpy as np

from ..scene import Camera, Scene
from ..scene.scene import instance_corners

FRAMING_VFOV_DEGREES = 40.0
LOOK_ALONG_PLUS_Z = (0.0, 0.0, 1.0)
LOOK_ALONG_MINUS_Z = (0.0, 0.0, -1.0)


def framing_camera(scene: Scene, forward=LOOK_ALONG_PLUS_Z) -> Camera:
    corners = [shape.world_vertices.reshape(-1, 3) for shape in scene.shapes if shape.triangle_count]
    corners += [instance_corners(instance) for instance in scene.instances]
    low, high = (np.min([c.min(axis=0) for c in corners], axis=0), np.max([c.max(axis=0) for c in corners], axis=0))
    centre = (low.astype(np.float64) + high) / 2.0
    radius = float(np.linalg.norm(high.astype(np.float64) - low)) / 2.0
    # a scene flat in every direction (one point) still gets a camera at a usable distance
    radius = max(radius, float(np.abs(centre).max()) * 1e-6, np.finfo(np.float32).tiny)
    distance = radius / math.sin(math.radians(FRAMING_VFOV_DEGREES) / 2.0)
    position = centre - distance * np.asarray(forward, dtype=np.float64)
    return Camera(tuple(position), forward, (0.0, 1.0, 0.0), FRAMING_VFOV_DEGREES)
