"""Coloured glass that absorbs inside (KHR_materials_volume, `volume`): a long smooth glass block
lying across the view and a rough transmissive Principled sphere, both absorbing, on a light floor
under a constant sky.

Light crossing the block's length loses far more than light crossing its width, so a wrong
distance (a segment measured outside, a ray direction not unit), a segment attenuated on the
wrong side of a face or an absorption coefficient of the wrong sign or scale changes the colour
along it. The sphere's rough transmission puts rays inside at every angle; its back faces also
reflect light inside, each reflection attenuated again. Both float a little above the floor: a
face that touched it would leave undefined which surface a ray inside meets first.
"""

from __future__ import annotations

from ..scene import Camera, Diffuse, Glass, Principled, Scene, make_box, make_icosphere, make_plane
from ..scene.lights.environment import Environment

SKY = (0.9, 0.95, 1.0)
# the colour white light turns after this many scene units inside
BLOCK_ATTENUATION = ((0.35, 0.75, 0.95), 0.6)
SPHERE_ATTENUATION = ((0.95, 0.55, 0.25), 0.5)


def absorbing_glass() -> Scene:
    block_color, block_distance = BLOCK_ATTENUATION
    sphere_color, sphere_distance = SPHERE_ATTENUATION
    block = Glass("blue_glass", ior=1.5, attenuation_color=block_color, attenuation_distance=block_distance)
    amber = Principled(
        "amber",
        base_color=(1.0, 1.0, 1.0),
        roughness=0.25,
        spec_trans=1.0,
        eta=1.5,
        attenuation_color=sphere_color,
        attenuation_distance=sphere_distance,
    )
    shapes = [
        make_plane((0.0, 0.0, 0.0), (0, 0, 0), (6.0, 6.0), Diffuse("floor", color=(0.75, 0.75, 0.72)), "floor"),
        make_box((-0.45, 0.3, 0.35), (0.0, -0.5, 0.0), (0.4, 0.5, 1.7), block, "block"),
        make_icosphere((0.75, 0.5, -0.2), (0, 0, 0), 0.45, 3, amber, "sphere"),
    ]
    camera = Camera.looking_at((0.3, 1.9, -3.0), (0.1, 0.3, 0.2), vfov_degrees=42.0)
    scene = Scene(shapes, camera)
    scene.environment = Environment(radiance=SKY)
    return scene
