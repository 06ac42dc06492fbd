"""Glossy spheres sweeping GGX roughness from 0.01 (almost a mirror: D peaks near 1 / (pi 1e-4))
to 1 (where single-scattering GGX loses the most energy), in the emitting room.

Errors in the microfacet distribution, in Smith's masking, in the visible-normal sampling or in
its pdf change the brightness and blur of the room's reflection by roughness.
"""

from __future__ import annotations

from ..scene import Camera, Glossy, Scene, make_icosphere
from .emitting_room import emitting_room

ROUGHNESS_SWEEP = (0.01, 0.05, 0.1, 0.25, 0.5, 1.0)
COLUMNS = 3
SPACING = 1.1
RADIUS = 0.45
ROOM_HALF_SIZE = 4.0
ROOM_CELLS = 8


def glossy_spheres() -> Scene:
    shapes = emitting_room(ROOM_HALF_SIZE, ROOM_CELLS)
    rows = -(-len(ROUGHNESS_SWEEP) // COLUMNS)
    for index, roughness in enumerate(ROUGHNESS_SWEEP):
        row, column = divmod(index, COLUMNS)
        # left to right, top to bottom in the picture (image right is -x for a camera looking along +z)
        position = ((COLUMNS - 1) / 2 - column) * SPACING, ((rows - 1) / 2 - row) * SPACING, 0.0
        metal = Glossy(f"glossy_{roughness:g}", color=(0.95, 0.8, 0.55), roughness=roughness)
        shapes.append(make_icosphere(position, (0, 0, 0), RADIUS, 3, metal, f"sphere_{roughness:g}"))
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -3.5), (0.0, 0.0, 0.0), vfov_degrees=50.0))
