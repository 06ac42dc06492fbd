"""Veach's door ajar: a closed room lit only through the gap of a door left ajar into a second
room, where the lamp is. The lamp hangs on the dividing wall's far side, facing away from the door,
so no straight line joins it to the camera's room: every path that lights the picture bounces off
the lit room's walls and finds the gap (mostly indirect light).

Path tracing from the camera must find the few-centimetre gap by chance and then the lamp behind
it; next-event estimation from the camera's room is always blocked. Bidirectional strategies start
on the lamp, fill the lit room and pass the gap from that side, where most of the light is.
"""

from __future__ import annotations

import math

import numpy as np

from ..scene import Camera, Diffuse, Emitter, Glossy, Scene, Shape, make_box, make_icosphere, model_matrix

# Both rooms share walls WALL_THICKNESS thick: the camera's room spans z from ROOM_FRONT to the
# dividing wall at DIVIDER_Z, the lit room from there to ROOM_BACK; x from -HALF_WIDTH to HALF_WIDTH.
HALF_WIDTH = 1.5
HEIGHT = 2.0
ROOM_FRONT = -2.0
DIVIDER_Z = 1.0
ROOM_BACK = 2.5
WALL_THICKNESS = 0.05
# The door fills the opening x in DOOR_X, y up to DOOR_HEIGHT, hinged at the opening's larger x and
# swung into the lit room by DOOR_AJAR_DEGREES: its free edge leaves a wedge-shaped gap.
DOOR_X = (0.2, 1.0)
DOOR_HEIGHT = 1.6
DOOR_THICKNESS = 0.04
DOOR_AJAR_DEGREES = 20.0
# The lamp: a square on the dividing wall's far side, away from the door, facing the lit room.
LAMP_CENTRE = (-0.9, 1.0)  # x, y
LAMP_HALF_SIZE = 0.4
LAMP_EMITTANCE = 250.0


def slab(name: str, low, high, material) -> Shape:
    """An axis-aligned box from corner `low` to corner `high`."""
    low, high = np.asarray(low, np.float64), np.asarray(high, np.float64)
    return make_box((low + high) / 2, (0, 0, 0), high - low, material, name)


def shell(white: Diffuse) -> list[Shape]:
    """Floor, ceiling and outer walls around both rooms, and the dividing wall around the opening."""
    h, t = HALF_WIDTH, WALL_THICKNESS
    left, right = DOOR_X
    wall = (DIVIDER_Z - t / 2, DIVIDER_Z + t / 2)
    return [
        slab("floor", (-h - t, -t, ROOM_FRONT - t), (h + t, 0, ROOM_BACK + t), white),
        slab("ceiling", (-h - t, HEIGHT, ROOM_FRONT - t), (h + t, HEIGHT + t, ROOM_BACK + t), white),
        slab("wall_left", (-h - t, 0, ROOM_FRONT), (-h, HEIGHT, ROOM_BACK), white),
        slab("wall_right", (h, 0, ROOM_FRONT), (h + t, HEIGHT, ROOM_BACK), white),
        slab("wall_front", (-h, 0, ROOM_FRONT - t), (h, HEIGHT, ROOM_FRONT), white),
        slab("wall_back", (-h, 0, ROOM_BACK), (h, HEIGHT, ROOM_BACK + t), white),
        slab("divider_left", (-h, 0, wall[0]), (left, HEIGHT, wall[1]), white),
        slab("divider_right", (right, 0, wall[0]), (h, HEIGHT, wall[1]), white),
        slab("divider_top", (left, DOOR_HEIGHT, wall[0]), (right, HEIGHT, wall[1]), white),
    ]


def door(material: Diffuse) -> Shape:
    """The door, closed in the opening, then turned about its hinge into the lit room."""
    left, right = DOOR_X
    closed = slab(
        "door",
        (left, 0, DIVIDER_Z - DOOR_THICKNESS / 2),
        (right, DOOR_HEIGHT, DIVIDER_Z + DOOR_THICKNESS / 2),
        material,
    )
    hinge = np.array([right, 0.0, DIVIDER_Z])
    # a positive turn about +y takes the free edge (smaller x) towards +z
    turn = model_matrix((0, 0, 0), (0, math.radians(DOOR_AJAR_DEGREES), 0), (1, 1, 1))
    matrix = model_matrix(hinge, (0, 0, 0), (1, 1, 1)) @ turn @ model_matrix(-hinge, (0, 0, 0), (1, 1, 1))
    return closed.transformed(matrix)


def lamp() -> Shape:
    """A square just off the dividing wall's far face, facing +z (into the lit room)."""
    x, y = LAMP_CENTRE
    s = LAMP_HALF_SIZE
    z = DIVIDER_Z + WALL_THICKNESS / 2 + 1e-3
    corners = np.array([(x - s, y - s, z), (x + s, y - s, z), (x + s, y + s, z), (x - s, y + s, z)], np.float32)
    light = Emitter("lamp", color=(1.0, 0.9, 0.75), emittance=LAMP_EMITTANCE)
    return Shape("lamp", corners[np.array([[0, 1, 2], [0, 2, 3]])], light)


def door_ajar() -> Scene:
    white = Diffuse("white", color=(0.75, 0.75, 0.72))
    wood = Diffuse("door", color=(0.55, 0.35, 0.2))
    shapes = [
        *shell(white),
        door(wood),
        lamp(),
        slab("table", (-1.2, 0, -0.6), (-0.5, 0.7, 0.2), Diffuse("table", color=(0.3, 0.45, 0.6))),
        make_icosphere(
            (0.4, 0.3, -0.3), (0, 0, 0), 0.3, 2, Glossy("metal", color=(0.9, 0.8, 0.6), roughness=0.15), "ball"
        ),
    ]
    camera = Camera.looking_at((-1.1, 1.3, -1.8), (0.5, 0.6, 1.0), vfov_degrees=60.0)
    return Scene(shapes, camera)
