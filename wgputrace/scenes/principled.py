"""Principled spheres: Mitsuba 3's `principled` material over metallic 0 to 1 and roughness 0.1
to 1, in the emitting room; `principled_transmission` the same room with spheres that transmit
(spec_trans 0.5 and 1, rough and smooth, one half metallic).

Errors in the Disney diffuse lobe (its retro-reflection grows with roughness), in the dielectric
and Schlick Fresnel terms mixed by metallic, or in the choice between the diffuse and specular
lobes change each sphere's brightness, tint and highlight; errors in the transmission lobe (its
sqrt(base_color) tint, the inside's eta, total internal reflection) change what shows through.
"""

from __future__ import annotations

from ..scene import Camera, Principled, Scene, make_icosphere
from .emitting_room import emitting_room

# (metallic, roughness) left to right, top to bottom in the picture
SWEEP = ((0.0, 0.1), (0.0, 0.5), (0.0, 1.0), (1.0, 0.1), (1.0, 0.5), (0.5, 0.3))
# (metallic, roughness, spec_trans) likewise
TRANSMISSION_SWEEP = (
    (0.0, 0.05, 1.0),
    (0.0, 0.4, 1.0),
    (0.0, 0.2, 0.5),
    (0.0, 1.0, 1.0),
    (0.5, 0.2, 1.0),
    (0.0, 0.1, 0.8),
)
BASE_COLOR = (0.9, 0.6, 0.3)
COLUMNS = 3
SPACING = 1.1
RADIUS = 0.45
ROOM_HALF_SIZE = 4.0
ROOM_CELLS = 8


def principled_spheres() -> Scene:
    return spheres_in_room([(m, r, 0.0) for m, r in SWEEP])


def principled_transmission() -> Scene:
    return spheres_in_room(TRANSMISSION_SWEEP)


def spheres_in_room(sweep) -> Scene:
    """Spheres of the principled material for each (metallic, roughness, spec_trans) of `sweep`."""
    shapes = emitting_room(ROOM_HALF_SIZE, ROOM_CELLS)
    rows = -(-len(sweep) // COLUMNS)
    for index, (metallic, roughness, spec_trans) in enumerate(sweep):
        row, column = divmod(index, COLUMNS)
        # image right is -x for a camera looking along +z
        position = ((COLUMNS - 1) / 2 - column) * SPACING, ((rows - 1) / 2 - row) * SPACING, 0.0
        label = f"m{metallic:g}_r{roughness:g}" + (f"_t{spec_trans:g}" if spec_trans else "")
        material = Principled(
            f"principled_{label}", BASE_COLOR, metallic=metallic, roughness=roughness, spec_trans=spec_trans
        )
        shapes.append(make_icosphere(position, (0, 0, 0), RADIUS, 3, material, f"sphere_{label}"))
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -3.5), (0.0, 0.0, 0.0), vfov_degrees=50.0))
