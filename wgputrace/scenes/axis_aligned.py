"""A camera looking exactly along +z at axis-aligned boxes in an axis-aligned room.

Every face is perpendicular to an axis, so bounding boxes are flat in one dimension (the floor,
the walls, a thin shelf) and many rays run nearly parallel to faces and slabs: where a slab test
computes 0 * inf, or a traversal misses a flat box, or an edge-on face (x = 0, in the camera's own
plane) is hit, the image shows holes, streaks or NaN.
"""

from __future__ import annotations

from ..scene import Camera, Diffuse, Emitter, Glossy, Scene, make_box

ROOM = (4.0, 3.0, 6.0)  # x, y, z extent; floor at y = -1, back wall at z = 2
ROOM_CENTRE = (0.0, 0.5, -1.0)


def axis_boxes() -> Scene:
    white = Diffuse("white", color=(0.75, 0.75, 0.72))
    red = Diffuse("red", color=(0.7, 0.12, 0.1))
    green = Diffuse("green", color=(0.15, 0.6, 0.15))
    mirror = Glossy("near_mirror", color=(0.9, 0.9, 0.9), roughness=0.02)
    lamp = Emitter("lamp", color=(1.0, 0.9, 0.8), emittance=12.0)
    (cx, cy, cz), (sx, sy, sz) = ROOM_CENTRE, ROOM
    thin = 0.05  # walls are flat boxes: two faces, four thin sides
    shapes = [
        make_box((cx, cy - sy / 2, cz), (0, 0, 0), (sx, thin, sz), white, "floor"),
        make_box((cx, cy + sy / 2, cz), (0, 0, 0), (sx, thin, sz), white, "ceiling"),
        make_box((cx, cy, cz + sz / 2), (0, 0, 0), (sx, sy, thin), white, "back_wall"),
        make_box((cx + sx / 2, cy, cz), (0, 0, 0), (thin, sy, sz), red, "wall_plus_x"),
        make_box((cx - sx / 2, cy, cz), (0, 0, 0), (thin, sy, sz), green, "wall_minus_x"),
        make_box((0.0, cy + sy / 2 - thin, 0.0), (0, 0, 0), (1.0, 0.01, 1.0), lamp, "lamp"),
        # two cubes stacked face to face, and one whose face x = 0 lies in the camera's plane
        make_box((-0.8, -0.5, 0.8), (0, 0, 0), (1.0, 1.0, 1.0), white, "cube_low"),
        make_box((-0.8, 0.25, 0.8), (0, 0, 0), (0.5, 0.5, 0.5), white, "cube_high"),
        make_box((0.3, -0.7, 0.0), (0, 0, 0), (0.6, 0.6, 0.6), white, "cube_at_x0"),
        make_box((0.9, 0.2, 1.0), (0, 0, 0), (1.0, 0.02, 1.0), white, "shelf"),
        make_box((1.1, -0.6, 1.2), (0, 0, 0), (0.8, 0.8, 0.8), mirror, "mirror_cube"),
    ]
    camera = Camera(position=(0.0, 0.0, -3.5), forward=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0), vfov_degrees=55.0)
    return Scene(shapes, camera)
