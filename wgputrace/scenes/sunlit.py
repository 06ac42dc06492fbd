"""A sunny scene whose lit sides are several times brighter than white: coloured spheres on a grey
ground under a small, bright sun and a blue sky. The picture the tone curves are shown on
(scripts/make_camera_pictures.py), and where clipping turns the orange sphere's lit side yellow and
AgX keeps it orange (`test_a_sunlit_orange_keeps_its_hue_in_the_png`)."""

from __future__ import annotations

from ..scene import Camera, Diffuse, Glossy, Scene, Sun, make_icosphere, make_plane
from ..scene.lights.environment import Environment

# The orange the tone curves are judged on: lit by the sun, about 3.7 times its albedo.
ORANGE = (0.9, 0.35, 0.08)
SUN_DIRECTION = (-0.45, -0.7, 0.55)  # the way the sunlight travels
SUN_IRRADIANCE = 10.0
SUN_COLOR = (1.0, 0.95, 0.85)
SKY = (0.3, 0.42, 0.7)


def sunlit_spheres() -> Scene:
    spheres = [
        ((-1.35, 0.45, 0.2), 0.45, Diffuse("orange", color=ORANGE)),
        ((-0.35, 0.4, 0.7), 0.4, Diffuse("blue", color=(0.1, 0.25, 0.8))),
        ((0.55, 0.45, 0.1), 0.45, Diffuse("green", color=(0.2, 0.65, 0.15))),
        ((1.45, 0.4, 0.8), 0.4, Glossy("gold", color=(1.0, 0.78, 0.34), roughness=0.15)),
        ((0.15, 0.25, -0.7), 0.25, Diffuse("white", color=(0.8, 0.8, 0.8))),
    ]
    shapes = [
        make_plane((0.0, 0.0, 0.5), (0, 0, 0), (14.0, 14.0), Diffuse("ground", color=(0.25, 0.25, 0.23)), "ground")
    ]
    shapes += [
        make_icosphere(centre, (0, 0, 0), radius, 3, material, material.name) for centre, radius, material in spheres
    ]
    scene = Scene(shapes, Camera.looking_at((0.3, 1.5, -3.6), (0.0, 0.35, 0.4), vfov_degrees=42.0))
    scene.environment = Environment(radiance=SKY)
    scene.add_light(Sun(SUN_DIRECTION, SUN_IRRADIANCE, color=SUN_COLOR, name="sun"))
    return scene
