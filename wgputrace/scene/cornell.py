"""The default scene: the Cornell box of listing 16 of the trac0r thesis.

Built in trac0r's coordinates with trac0r's parameters, then reflected across x = 0 so that a
right-handed camera shows the thesis's picture (red wall left, green right). trac0r passed a
field of view of "90" but its screen mapping halved the tangent: 2 atan(0.5 tan 45deg).
"""

from __future__ import annotations

import math

import numpy as np

from .cameras import Camera
from .materials import Diffuse, Emitter, Glass, Glossy
from .scene import Scene
from .shapes import make_box, make_icosphere, make_plane

CORNELL_VFOV_DEGREES = math.degrees(2.0 * math.atan(0.5 * math.tan(math.radians(45.0))))
_MIRROR_X = np.diag([-1.0, 1.0, 1.0])


def cornell_box() -> Scene:
    emissive = Emitter("emissive", color=(1.0, 0.93, 0.85), emittance=15.0)
    white = Diffuse("white", color=(0.740063, 0.742313, 0.733934))
    red = Diffuse("red", color=(0.366046, 0.0371827, 0.0416385))
    green = Diffuse("green", color=(0.162928, 0.408903, 0.0833759))
    glass = Glass("glass", color=(0.5, 0.5, 0.9), ior=1.51714)
    glossy = Glossy("glossy", color=(1.0, 1.0, 1.0), roughness=0.09)
    half_pi = math.pi / 2.0
    shapes = [
        make_plane((-0.5, 0.4, 0.0), (0, 0, -half_pi), (1, 1), red, "wall_left"),
        make_plane((0.5, 0.4, 0.0), (0, 0, half_pi), (1, 1), green, "wall_right"),
        make_plane((0.0, 0.4, 0.5), (-half_pi, 0, 0), (1, 1), white, "wall_back"),
        make_plane((0.0, 0.9, 0.0), (math.pi, 0, 0), (1, 1), white, "wall_top"),
        make_plane((0.0, -0.1, 0.0), (0, 0, 0), (1, 1), white, "wall_bottom"),
        make_plane((0.0, 0.85, -0.1), (0, 0, 0), (0.4, 0.4), emissive, "lamp"),
        make_box((0.3, 0.1, 0.1), (0, 0.6, 0), (0.2, 0.5, 0.2), white, "box1"),
        make_box((-0.2, 0.15, 0.1), (0, -0.5, 0), (0.3, 0.6, 0.3), glossy, "box2"),
        make_icosphere((0.0, 0.1, -0.3), (0, 0, 0), 0.15, 2, glass, "sphere1"),
        make_icosphere((0.3, 0.45, 0.1), (0, 0, 0), 0.15, 2, glossy, "sphere2"),
    ]
    camera = Camera(position=(0.0, 0.31, -1.2), forward=(0, 0, 1), up=(0, 1, 0), vfov_degrees=CORNELL_VFOV_DEGREES)
    return Scene([shape.transformed(_MIRROR_X) for shape in shapes], camera)
