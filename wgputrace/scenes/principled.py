"""Principled spheres: Mitsuba 3's `principled` material over metallic 0 to 1 and roughness 0.1
to 1, in the emitting room; `principled_transmission` the same room with spheres that transmit
(spec_trans 0.5 and 1, rough and smooth, one half metallic); `principled_clearcoat` rough red
spheres under a clearcoat from rough to glossy (one over a half metal); `principled_sheen`
cloth-like spheres (a dark rough base) with a white, a half-tinted and a tinted sheen.

Errors in the Disney diffuse lobe (its retro-reflection grows with roughness), in the dielectric
and Schlick Fresnel terms mixed by metallic, or in the choice between the diffuse and specular
lobes change each sphere's brightness, tint and highlight; errors in the transmission lobe (its
sqrt(base_color) tint, the inside's eta, total internal reflection) change what shows through;
errors in the clearcoat (its GTR1 width, Fresnel, weight or sampling rate) change its white
highlight over the red, errors in the sheen (its grazing weight, tint) the bright rims.
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
# (metallic, roughness, spec_trans, clearcoat, clearcoat_gloss) likewise
CLEARCOAT_SWEEP = ((0.0, 0.6, 0.0, 1.0, 0.0), (0.0, 0.6, 0.0, 1.0, 0.7), (0.5, 0.6, 0.0, 0.5, 0.95))
# (metallic, roughness, spec_trans, sheen, sheen_tint) likewise
SHEEN_SWEEP = ((0.0, 1.0, 0.0, 1.0, 0.0), (0.0, 1.0, 0.0, 1.0, 0.5), (0.0, 0.8, 0.0, 0.6, 1.0))
BASE_COLOR = (0.9, 0.6, 0.3)
COATED_COLOR = (0.6, 0.05, 0.05)
CLOTH_COLOR = (0.1, 0.1, 0.35)
COLUMNS = 3
SPACING = 1.1
RADIUS = 0.45
ROOM_HALF_SIZE = 4.0
ROOM_CELLS = 8


def principled_spheres() -> Scene:
    return spheres_in_room([(m, r, 0.0) for m, r in SWEEP])


def principled_transmission() -> Scene:
    return spheres_in_room(TRANSMISSION_SWEEP)


def principled_clearcoat() -> Scene:
    return spheres_in_room(CLEARCOAT_SWEEP, COATED_COLOR, ("clearcoat", "clearcoat_gloss"))


def principled_sheen() -> Scene:
    return spheres_in_room(SHEEN_SWEEP, CLOTH_COLOR, ("sheen", "sheen_tint"))


def spheres_in_room(sweep, base_color=BASE_COLOR, lobe: tuple[str, ...] = ()) -> Scene:
    """Spheres of the principled material of `base_color` for each (metallic, roughness, spec_trans,
    *the values of the `lobe` parameters) of `sweep`."""
    shapes = emitting_room(ROOM_HALF_SIZE, ROOM_CELLS)
    rows = -(-len(sweep) // COLUMNS)
    for index, (metallic, roughness, spec_trans, *values) in enumerate(sweep):
        row, column = divmod(index, COLUMNS)
        # image right is -x for a camera looking along +z
        position = ((COLUMNS - 1) / 2 - column) * SPACING, ((rows - 1) / 2 - row) * SPACING, 0.0
        label = f"m{metallic:g}_r{roughness:g}" + (f"_t{spec_trans:g}" if spec_trans else "")
        label += "".join(f"_{name}{value:g}" for name, value in zip(lobe, values, strict=True))
        material = Principled(
            f"principled_{label}",
            base_color,
            metallic=metallic,
            roughness=roughness,
            spec_trans=spec_trans,
            **dict(zip(lobe, values, strict=True)),
        )
        shapes.append(make_icosphere(position, (0, 0, 0), RADIUS, 3, material, f"sphere_{label}"))
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -3.5), (0.0, 0.0, 0.0), vfov_degrees=50.0))
