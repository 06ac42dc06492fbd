"""Point, spot and directional lights (delta lights: only light sampling reaches them) in an open
room: a floor, a back wall, a box and a sphere, nothing else lit and a black background.

Each light has a colour of its own, so a wrong one shows as a wrong hue: a warm point light above
the left, whose 1/d^2 falloff shades the floor and the wall; a cool spot light looking down at the
floor on the right, its beam's full circle and linear falloff to the cutoff drawn on the floor and
the box; a green directional light grazing from the left, casting the sphere's and the box's long
sharp shadows.
"""

from __future__ import annotations

from ..scene import (
    Camera,
    Diffuse,
    DirectionalLight,
    PointLight,
    Scene,
    SpotLight,
    make_box,
    make_icosphere,
    make_plane,
)


def point_spot_directional() -> Scene:
    white = Diffuse("white", color=(0.75, 0.75, 0.75))
    clay = Diffuse("clay", color=(0.7, 0.4, 0.3))
    shapes = [
        make_plane((0.0, 0.0, 0.0), (0, 0, 0), (5.0, 4.0), white, "floor"),
        make_box((0.0, 1.25, 2.05), (0, 0, 0), (5.0, 2.5, 0.1), white, "back_wall"),
        make_box((0.9, 0.35, 0.6), (0, 0.4, 0), (0.7, 0.7, 0.7), white, "box"),
        make_icosphere((-0.7, 0.45, 0.3), (0, 0, 0), 0.45, 3, clay, "sphere"),
    ]
    scene = Scene(shapes, Camera.looking_at((0.0, 1.7, -3.2), (0.0, 0.6, 0.8), vfov_degrees=50.0))
    scene.add_light(
        PointLight((-1.2, 1.8, -0.2), 2.5, color=(1.0, 0.8, 0.6), name="warm_point"),
        SpotLight(
            (1.0, 2.4, -0.2),
            (0.05, -1.0, 0.35),
            12.0,
            cutoff_angle_degrees=30.0,
            beam_width_degrees=18.0,
            color=(0.6, 0.8, 1.0),
            name="cool_spot",
        ),
        DirectionalLight((1.0, -0.35, 0.25), 0.6, color=(0.3, 1.0, 0.4), name="green_sun"),
    )
    return scene
