"""A glass sphere on a diffuse floor under a small lamp: the sphere focuses the lamp into a bright
caustic on the floor beside its shadow.

The caustic's light reaches the floor only through the glass, so next-event estimation (whose
shadow rays the sphere blocks) never sees it; a path from the camera must bounce off the floor,
pass the sphere twice and then hit the small lamp by chance. Light paths start on the lamp,
refract through the sphere and land on the floor where the caustic is, and connect to the camera
from there. `caustic_mask` marks the floor pixels the caustic falls on, where the benchmarks
measure its error.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Diffuse, Glass, Scene, make_icosphere
from .stage import backdrop, floor, square_lamp

FLOOR_HALF_SIZE = 3.0
WALL_Z = 2.5
SPHERE_CENTRE = (0.0, 0.4, 0.0)
SPHERE_RADIUS = 0.4
SPHERE_IOR = 1.5
# A small, bright square lamp above and behind the sphere, facing down: the line from it through
# the sphere's centre meets the floor in front of the sphere, near the glass ball's focus.
LAMP_CENTRE = (0.0, 1.4, 1.6)
LAMP_SIZE = 0.12
LAMP_EMITTANCE = 600.0
# The caustic lies on the floor about the lamp's image through the sphere's centre, within this
# many sphere radii of it (the flat facets and the lamp's size spread it).
CAUSTIC_RADIUS_IN_RADII = 1.0


def caustic() -> Scene:
    white = Diffuse("floor", color=(0.8, 0.8, 0.8))
    glass = Glass("glass", color=(1.0, 1.0, 1.0), ior=SPHERE_IOR)
    shapes = [
        floor(white, 2 * FLOOR_HALF_SIZE),
        backdrop(white, "wall", WALL_Z, (2 * FLOOR_HALF_SIZE, FLOOR_HALF_SIZE)),
        square_lamp(LAMP_CENTRE, LAMP_SIZE, LAMP_EMITTANCE),
        make_icosphere(SPHERE_CENTRE, (0, 0, 0), SPHERE_RADIUS, 3, glass, "sphere"),
    ]
    camera = Camera.looking_at((0.0, 1.6, -2.6), (0.0, 0.2, 0.0), vfov_degrees=40.0)
    return Scene(shapes, camera)


def caustic_centre() -> np.ndarray:
    """Where the line from the lamp's centre through the sphere's centre meets the floor (y = 0)."""
    lamp, centre = np.asarray(LAMP_CENTRE, np.float64), np.asarray(SPHERE_CENTRE, np.float64)
    direction = centre - lamp
    return lamp + direction * (-lamp[1] / direction[1])


def caustic_mask(camera: Camera, width: int, height: int) -> np.ndarray:
    """(height, width) bool: pixels whose centre's camera ray meets the floor within the caustic's
    radius of `caustic_centre` without meeting the sphere first."""
    right, up, forward = camera.image_plane(width, height)
    x = (np.arange(width) + 0.5) / width * 2.0 - 1.0
    y = (np.arange(height) + 0.5) / height * 2.0 - 1.0
    directions = forward + x[None, :, None] * right - y[:, None, None] * up
    directions /= np.linalg.norm(directions, axis=-1, keepdims=True)
    origin = np.asarray(camera.position, np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        floor_distance = -origin[1] / directions[..., 1]
    hit = origin + directions * floor_distance[..., None]
    on_floor = (floor_distance > 0) & (
        np.linalg.norm(hit - caustic_centre(), axis=-1) < CAUSTIC_RADIUS_IN_RADII * SPHERE_RADIUS
    )
    # the sphere hides the floor where the ray passes within its radius of the centre before the floor
    to_centre = np.asarray(SPHERE_CENTRE, np.float64) - origin
    along = directions @ to_centre
    miss_distance = np.linalg.norm(to_centre - along[..., None] * directions, axis=-1)
    hidden = (miss_distance < SPHERE_RADIUS) & (along > 0) & (along < floor_distance)
    return on_floor & ~hidden
