"""Scenes lit by the environment alone: a generated sky with a small, very bright sun, a constant
sky, and a map black but for one texel (the direction convention's pin)."""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Diffuse, Glossy, Scene, make_box, make_icosphere, make_plane
from ..scene.lights.environment import Environment, local_of_uv

# The sunny sky: width x height texels (Mitsuba's envmap needs at least 2 x 3).
SKY_SIZE = (128, 64)
SKY_ZENITH = np.array([0.25, 0.45, 0.9])
SKY_HORIZON = np.array([0.9, 0.95, 1.0])
SKY_GROUND = np.array([0.2, 0.18, 0.15])
# A disc of texels around SUN_DIRECTION (where the light comes FROM): a few texels of 1.4 x 2.8
# degrees, bright enough to give about three times the sky's irradiance on the ground.
SUN_DIRECTION = np.array([0.55, 0.62, 0.56])
SUN_RADIUS_DEGREES = 2.5
SUN_RADIANCE = np.array([1500.0, 1400.0, 1200.0])

CONSTANT_SKY = (0.8, 0.9, 1.1)

# One bright texel of a small map, placed so that its direction is on no axis and in no symmetry
# plane: (row, column) of a width x height map, its radiance, and the map's rotation about +y.
ONE_TEXEL_SIZE = (16, 9)
ONE_TEXEL = (2, 3)
ONE_TEXEL_RADIANCE = 20.0
ONE_TEXEL_ROTATION_DEGREES = 30.0


def texel_directions(width: int, height: int) -> np.ndarray:
    """(height, width, 3) unit directions of the texels of a map in its own frame (Mitsuba's
    convention: column centres at u = (i + 1/2) / W, rows at v = j / (H - 1))."""
    u = (np.arange(width) + 0.5) / width
    v = np.arange(height) / (height - 1)
    uv = np.stack(np.meshgrid(u, v), axis=-1).reshape(-1, 2)
    return local_of_uv(uv).reshape(height, width, 3)


def sunny_sky() -> np.ndarray:
    """float32 (H, W, 3): a sky brightening from zenith to horizon, a dim ground below, and a sun."""
    directions = texel_directions(*SKY_SIZE)
    up = directions[..., 1:2]
    elevation = np.clip(up, 0.0, 1.0) ** 0.5
    texels = np.where(up >= 0.0, SKY_HORIZON + (SKY_ZENITH - SKY_HORIZON) * elevation, SKY_GROUND)
    sun = SUN_DIRECTION / np.linalg.norm(SUN_DIRECTION)
    in_sun = directions @ sun >= np.cos(np.radians(SUN_RADIUS_DEGREES))
    texels[in_sun] = SUN_RADIANCE
    return texels.astype(np.float32)


def one_texel_map() -> np.ndarray:
    """float32 (H, W, 3): black but for texel ONE_TEXEL, white of ONE_TEXEL_RADIANCE."""
    width, height = ONE_TEXEL_SIZE
    texels = np.zeros((height, width, 3), np.float32)
    texels[ONE_TEXEL] = ONE_TEXEL_RADIANCE
    return texels


def one_texel_uv() -> np.ndarray:
    """(1, 2): the map coordinates of the bright texel (Environment.direction takes them)."""
    (width, height), (row, column) = ONE_TEXEL_SIZE, ONE_TEXEL
    return np.array([[(column + 0.5) / width, row / (height - 1)]])


def _spheres_on_a_plane(ground_color) -> list:
    ground = Diffuse("ground", color=ground_color)
    clay = Diffuse("clay", color=(0.7, 0.35, 0.2))
    metal = Glossy("metal", color=(0.9, 0.9, 0.85), roughness=0.15)
    return [
        make_plane((0.0, 0.0, 0.0), (0, 0, 0), (6.0, 6.0), ground, "ground"),
        make_icosphere((-0.6, 0.5, 0.0), (0, 0, 0), 0.5, 3, clay, "diffuse_sphere"),
        make_icosphere((0.6, 0.5, 0.3), (0, 0, 0), 0.5, 3, metal, "glossy_sphere"),
    ]


def env_sun_spheres() -> Scene:
    """A diffuse and a glossy sphere on a plane under `sunny_sky()`: the sun's few texels carry
    most of the light (sharp shadows, a highlight only importance sampling of the map finds often),
    the sky gives soft shadows, and camera rays see the sky, testing the map's lookup directly."""
    camera = Camera.looking_at((0.0, 1.6, -3.6), (0.0, 0.45, 0.0), vfov_degrees=45.0)
    scene = Scene(_spheres_on_a_plane((0.5, 0.5, 0.5)), camera)
    scene.environment = Environment(texels=sunny_sky(), source="sunny_sky")
    return scene


def constant_env() -> Scene:
    """A box, a diffuse and a glossy sphere on a plane under a constant, bluish sky: ambient
    occlusion only, no direction to get wrong, all of it from the escaped rays' MIS weights."""
    white = Diffuse("white", color=(0.8, 0.8, 0.8))
    shapes = [*_spheres_on_a_plane((0.6, 0.55, 0.5)), make_box((0.1, 0.3, 1.1), (0, 0.5, 0), (0.6, 0.6, 0.6), white)]
    camera = Camera.looking_at((0.0, 1.8, -3.4), (0.0, 0.4, 0.4), vfov_degrees=45.0)
    scene = Scene(shapes, camera)
    scene.environment = Environment(radiance=CONSTANT_SKY)
    return scene


def env_one_texel() -> Scene:
    """A diffuse sphere under `one_texel_map()`, turned by ONE_TEXEL_ROTATION_DEGREES: only the
    side facing the texel's documented direction (`Environment.direction`) is lit, so a mirrored or
    shifted convention lights another side."""
    ball = make_icosphere((0.0, 0.0, 0.0), (0, 0, 0), 1.0, 3, Diffuse("ball", color=(0.8, 0.8, 0.8)), "ball")
    # from below and off every axis: the lit cap (above, towards the camera's right) and the dark
    # underside are both in view
    scene = Scene([ball], Camera.looking_at((1.2, -0.8, -3.0), (0.0, 0.0, 0.0), vfov_degrees=50.0))
    scene.environment = Environment(
        texels=one_texel_map(), rotation_degrees=ONE_TEXEL_ROTATION_DEGREES, source="one_texel_map"
    )
    return scene
