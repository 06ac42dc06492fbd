"""Glass seen at grazing angles, in the emitting room: Fresnel near 90 degrees and total internal
reflection, where refraction code usually goes wrong (NaN from sqrt of a negative cos^2, energy
gained or lost at the critical angle, the wrong relative ior on the way out).

A clear sphere shows the room refracted and, along its silhouette, grazing reflections and rays
trapped by total internal reflection. A tinted slab lies almost edge-on to the camera: its top
face reflects at grazing incidence, light entering its front face is totally reflected inside by
the top and bottom faces, and its tint is applied at every crossing.
"""

from __future__ import annotations

from ..scene import Camera, Glass, Scene, make_box, make_icosphere
from .emitting_room import emitting_room

ROOM_HALF_SIZE = 4.0
ROOM_CELLS = 8


def glass_grazing() -> Scene:
    clear = Glass("clear_glass", color=(1.0, 1.0, 1.0), ior=1.5)
    tinted = Glass("tinted_glass", color=(0.95, 0.8, 0.6), ior=1.7)
    sphere = make_icosphere((0.45, 0.62, 0.5), (0, 0, 0), 0.55, 3, clear, "sphere")
    slab = make_box((-0.35, -0.25, 0.2), (0.02, 0.35, 0.0), (1.6, 0.2, 1.8), tinted, "slab")
    camera = Camera.looking_at((0.0, 0.3, -3.0), (0.0, 0.15, 0.4), vfov_degrees=40.0)
    return Scene([*emitting_room(ROOM_HALF_SIZE, ROOM_CELLS), sphere, slab], camera)
