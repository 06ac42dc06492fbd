"""The pieces of a stage for a few objects under a small lamp: a square floor in the plane y = 0, a
backdrop standing on it across the view, and a small warm square lamp facing down. The caustic and
glossy_through_glossy scenes are built of them."""

from __future__ import annotations

import numpy as np

from ..scene import Emitter, Material, Shape, make_plane

# a warm white, as a halogen lamp's
LAMP_COLOR = (1.0, 0.95, 0.85)


def floor(material: Material, side: float) -> Shape:
    """A square of `side` in the plane y = 0, centred on the origin, facing up."""
    return make_plane((0, 0, 0), (0, 0, 0), (side, side), material, "floor")


def backdrop(material: Material, name: str, z: float, size: tuple[float, float]) -> Shape:
    """A rectangle of `size` (width along x, height) standing on the floor at `z`, facing -z."""
    width, height = size
    return make_plane((0, height / 2, z), (-np.pi / 2, 0, 0), (width, height), material, name)


def square_lamp(centre, side: float, emittance: float) -> Shape:
    """An Emitter square of `side` at `centre`, facing down."""
    lamp = Emitter("lamp", color=LAMP_COLOR, emittance=emittance)
    return make_plane(centre, (np.pi, 0, 0), (side, side), lamp, "lamp")
