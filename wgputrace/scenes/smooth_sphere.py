"""A smooth low-poly sphere beside its flat version: two 80-triangle icospheres, the upper one with
the sphere's normals at its corners (smooth shading), the lower one flat, lit from the side by a
point light so that the shadow terminator runs down the middle of both as the camera sees them,
under a dim sky that keeps their shadowed halves visible.

Here shading normals break what they break: on a coarse smooth mesh the light reaches points
whose own facet faces away from it, whose shadow rays then meet the sphere itself, in hard
facet-shaped steps (the shadow terminator). Mitsuba 3 renders the scene as its reference with
the corner normals as its vertex normals and no terminator term: ours matches it with the term
off (SHADING_NORMAL_CASES), and with it on it fades those steps out.
"""

from __future__ import annotations

from ..scene import Camera, Diffuse, PointLight, Scene, make_icosphere
from ..scene.lights.environment import Environment

RADIUS = 0.5
CENTRE_Y = 0.55
ITERATIONS = 1  # 80 triangles: facets the size of the terminator's steps
# turned off the axes, so that no facet edge lines up with the light or the camera
ORIENTATION = (0.3, 0.2, 0.1)
GREY = (0.8, 0.8, 0.8)
# from the picture's left (+x), a little towards the camera and above
LIGHT_POSITION = (6.0, 1.0, -1.5)
LIGHT_INTENSITY = 45.0
SKY_RADIANCE = 0.05
CAMERA_POSITION = (0.0, 0.0, -3.0)
VFOV_DEGREES = 42.0


def smooth_sphere(smooth: bool = True) -> Scene:
    """The scene; `smooth` False drops the upper sphere's normals (both flat)."""
    material = Diffuse("grey", GREY)
    shapes = [
        make_icosphere((0.0, CENTRE_Y, 0.0), ORIENTATION, RADIUS, ITERATIONS, material, "smooth", smooth=smooth),
        make_icosphere((0.0, -CENTRE_Y, 0.0), ORIENTATION, RADIUS, ITERATIONS, material, "flat"),
    ]
    scene = Scene(shapes, Camera.looking_at(CAMERA_POSITION, (0.0, 0.0, 0.0), vfov_degrees=VFOV_DEGREES))
    scene.environment = Environment(radiance=SKY_RADIANCE)
    scene.add_light(PointLight(LIGHT_POSITION, LIGHT_INTENSITY))
    return scene
