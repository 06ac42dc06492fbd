"""The camera kinds' reference scenes, each made for what its camera does to a picture.

- `depth_of_field`: a thin lens focused on the middle of three spheres, one near the lens, one far
  behind, before a wall of black and white stripes: a wrong aperture, focus distance or lens
  sampling moves the blur of the near and far edges, which the blocks of a reference test see.
- `orthographic_boxes`: boxes of one size in a row going away from the camera, a sphere and their
  sharp shadows, seen along a diagonal by an orthographic camera: the row shows no perspective,
  and a wrong extent, aspect or ray origin moves every edge.
"""

from __future__ import annotations

from ..scene import (
    Diffuse,
    DirectionalLight,
    Emitter,
    OrthographicCamera,
    Scene,
    ThinLensCamera,
    make_box,
    make_icosphere,
    make_plane,
)
from ..scene.lights.environment import Environment

SKY = (0.45, 0.5, 0.6)
# The thin lens: its aperture and where it looks; the middle sphere sits at the focus distance.
LENS_POSITION = (0.0, 0.55, -3.0)
FOCUS_DISTANCE = 3.0
APERTURE_RADIUS = 0.12
STRIPES = 9
STRIPE_WALL_Z = 3.5


def depth_of_field() -> Scene:
    white = Diffuse("white", color=(0.8, 0.8, 0.78))
    black = Diffuse("black", color=(0.03, 0.03, 0.03))
    shapes = [
        make_plane((0.0, 0.0, 0.5), (0, 0, 0), (8.0, 10.0), Diffuse("floor", color=(0.5, 0.45, 0.4)), "floor"),
        make_icosphere((-0.45, 0.3, -1.6), (0, 0, 0), 0.3, 3, Diffuse("red", color=(0.75, 0.1, 0.08)), "near"),
        make_icosphere((0.0, 0.35, 0.0), (0, 0, 0), 0.35, 3, Diffuse("green", color=(0.15, 0.6, 0.2)), "in_focus"),
        make_icosphere((0.9, 0.5, 2.4), (0, 0, 0), 0.5, 3, Diffuse("blue", color=(0.1, 0.2, 0.75)), "far"),
        make_plane((0.0, 3.0, 0.0), (3.14159265, 0, 0), (2.0, 2.0), Emitter("lamp", emittance=4.0), "lamp"),
    ]
    # the wall behind: vertical stripes, alternately white and black
    width = 6.0 / STRIPES
    for k in range(STRIPES):
        material = white if k % 2 == 0 else black
        x = -3.0 + (k + 0.5) * width
        shapes.append(make_box((x, 1.5, STRIPE_WALL_Z), (0, 0, 0), (width, 3.0, 0.05), material, f"stripe_{k}"))
    camera = ThinLensCamera.looking_at(
        LENS_POSITION,
        (0.0, 0.35, 0.0),
        vfov_degrees=32.0,
        aperture_radius=APERTURE_RADIUS,
        focus_distance=FOCUS_DISTANCE,
    )
    scene = Scene(shapes, camera)
    scene.environment = Environment(radiance=SKY)
    return scene


def orthographic_boxes() -> Scene:
    clay = Diffuse("clay", color=(0.7, 0.45, 0.3))
    shapes = [make_plane((0.0, 0.0, 1.0), (0, 0, 0), (6.0, 8.0), Diffuse("floor", color=(0.7, 0.7, 0.68)), "floor")]
    shapes += [make_box((-0.8, 0.3, -0.5 + 0.9 * k), (0, 0, 0), (0.6, 0.6, 0.6), clay, f"box_{k}") for k in range(4)]
    shapes.append(make_icosphere((0.7, 0.4, 0.6), (0, 0, 0), 0.4, 3, Diffuse("teal", color=(0.1, 0.5, 0.5)), "sphere"))
    camera = OrthographicCamera.looking_at((2.6, 3.0, -3.0), (0.0, 0.3, 0.9), view_height=3.4)
    scene = Scene(shapes, camera)
    scene.environment = Environment(radiance=SKY)
    scene.add_light(DirectionalLight((-0.5, -1.0, 0.35), 2.5, color=(1.0, 0.95, 0.85), name="sun"))
    return scene
