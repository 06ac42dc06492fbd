"""Principled spheres: Mitsuba 3's `principled` material over metallic 0 to 1 and roughness 0.1
to 1, in the emitting room.

Errors in the Disney diffuse lobe (its retro-reflection grows with roughness), in the dielectric
and Schlick Fresnel terms mixed by metallic, or in the choice between the diffuse and specular
lobes change each sphere's brightness, tint and highlight.
"""

from __future__ import annotations

from ..scene import Camera, Principled, Scene, make_icosphere
from .emitting_room import emitting_room

# (metallic, roughness) left to right, top to bottom in the picture
SWEEP = ((0.0, 0.1), (0.0, 0.5), (0.0, 1.0), (1.0, 0.1), (1.0, 0.5), (0.5, 0.3))
BASE_COLOR = (0.9, 0.6, 0.3)
COLUMNS = 3
SPACING = 1.1
RADIUS = 0.45
ROOM_HALF_SIZE = 4.0
ROOM_CELLS = 8


def principled_spheres() -> Scene:
    shapes = emitting_room(ROOM_HALF_SIZE, ROOM_CELLS)
    rows = -(-len(SWEEP) // COLUMNS)
    for index, (metallic, roughness) in enumerate(SWEEP):
        row, column = divmod(index, COLUMNS)
        # image right is -x for a camera looking along +z
        position = ((COLUMNS - 1) / 2 - column) * SPACING, ((rows - 1) / 2 - row) * SPACING, 0.0
        name = f"principled_m{metallic:g}_r{roughness:g}"
        material = Principled(name, BASE_COLOR, metallic=metallic, roughness=roughness)
        shapes.append(make_icosphere(position, (0, 0, 0), RADIUS, 3, material, f"sphere_m{metallic:g}_r{roughness:g}"))
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -3.5), (0.0, 0.0, 0.0), vfov_degrees=50.0))
