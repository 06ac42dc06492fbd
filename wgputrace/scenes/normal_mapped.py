"""A normal-mapped plane under a grazing light: a Principled square facing the camera, its normal
map round bumps tilting up to 30 degrees (textured_asset's map at twice its scale), lit by a
directional light 10 degrees above its plane, under a dim sky.

At this angle the bumps' sides facing away from the light turn their shading normal below it
(black, as the geometry shadows them: no light through the surface), the sides facing it light up
far brighter than the flat plane would, and the terminator terms matter: ours (Chiang et al. 2019)
and Mitsuba's (Estevez et al. 2019 in its `normalmap`) differ there, so the reference comparison
turns both off (SHADING_NORMAL_CASES).
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, DirectionalLight, Principled, Scene, Shape
from ..scene.lights.environment import Environment
from .textured_asset import normal_texture

HALF_SIZE = 1.0
# textured_asset's bumps tilt 15 degrees at their rim; x and y doubled: about 28
NORMAL_SCALE = 2.0
BASE_COLOR = (0.7, 0.6, 0.5)
ROUGHNESS = 0.5
LIGHT_ELEVATION_DEGREES = 10.0
LIGHT_IRRADIANCE = 4.0
SKY_RADIANCE = 0.05


def normal_mapped_plane() -> Scene:
    h = HALF_SIZE
    # in z = 0 facing +z (the camera), uv (0, 0) at the top-left, u along +x: Mitsuba's dP/du frame
    corners = np.array([(-h, h, 0), (h, h, 0), (h, -h, 0), (-h, -h, 0)], np.float32)
    uv = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], np.float32)
    faces = np.array([[0, 2, 1], [0, 3, 2]])
    material = Principled(
        "bumps", BASE_COLOR, roughness=ROUGHNESS, normal_texture=normal_texture(), normal_scale=NORMAL_SCALE
    )
    scene = Scene(
        [Shape("plane", corners[faces], material, uvs=uv[faces])],
        Camera.looking_at((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), vfov_degrees=40.0),
    )
    elevation = np.radians(LIGHT_ELEVATION_DEGREES)
    # travelling towards -x and into the plane: from the picture's right (image right is +x here)
    scene.add_light(DirectionalLight((-np.cos(elevation), 0.0, -np.sin(elevation)), LIGHT_IRRADIANCE))
    scene.environment = Environment(radiance=SKY_RADIANCE)
    return scene
