"""`principled_anisotropic`: Principled's anisotropy (Mitsuba 3's `principled` `anisotropic`) in the
emitting room, whose checkered walls its reflections blur along the tangent.

Top row: brushed metal quads whose texture coordinates run along x, along the diagonal and along y
(the frame's tangent is dP/du, so the blur turns with them). Bottom row: smooth icospheres without
texture coordinates, whose tangent is Mitsuba's fallback (the first axis of coordinate_system of
each triangle's normal, made perpendicular to the shading normal): an anisotropic metal, a half
metallic anisotropic glossy and an anisotropic rough glass (the transmission's GGX is anisotropic
too). The camera looks along -z, so that the fallback frame's one singular normal (-z) faces away.

Errors in the frame (the tangent's source, its sign, the fallback) turn the blur; errors in the
alphas or in the visible-normal sampling change its width and brightness.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Principled, Scene, Shape, make_icosphere
from .emitting_room import emitting_room
from .principled import RADIUS, ROOM_CELLS, ROOM_HALF_SIZE, SPACING

# the quads' texture coordinates turned by these (degrees): the tangent along x, the diagonal, y
UV_TURNS = (0.0, 45.0, 90.0)
# (metallic, roughness, spec_trans, anisotropic) of the spheres, left to right
SPHERES = ((1.0, 0.3, 0.0, 1.0), (0.5, 0.4, 0.0, 0.8), (0.0, 0.3, 1.0, 1.0))
BRUSHED = dict(metallic=1.0, roughness=0.15, anisotropic=1.0)
METAL_COLOR = (0.9, 0.9, 0.9)
HALF_SIZE = 0.45
# the quads lean back (about x) so that they reflect the ceiling as well as the wall behind the camera
LEAN_DEGREES = 20.0


def brushed_quad(center, uv_turn_degrees: float, name: str) -> Shape:
    """A square facing +z (leaning back), its texture coordinates turned about their centre."""
    lean = np.radians(LEAN_DEGREES)
    right = np.array([HALF_SIZE, 0.0, 0.0])
    up = HALF_SIZE * np.array([0.0, np.cos(lean), -np.sin(lean)])
    corners = np.asarray(center) + np.array([-right + up, right + up, right - up, -right - up])
    turn = np.radians(uv_turn_degrees)
    rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    # glTF's convention: v runs down the image
    uvs = (np.array([(0, 0), (1, 0), (1, 1), (0, 1)]) - 0.5) @ rotation.T + 0.5
    faces = np.array([[0, 2, 1], [0, 3, 2]])  # wound to face +z
    material = Principled(f"brushed_{uv_turn_degrees:g}", METAL_COLOR, **BRUSHED)
    return Shape(name, corners[faces], material, uvs=uvs[faces])


def principled_anisotropic() -> Scene:
    shapes = emitting_room(ROOM_HALF_SIZE, ROOM_CELLS)
    for column, turn in enumerate(UV_TURNS):
        # image right is +x for a camera looking along -z
        shapes.append(brushed_quad(((column - 1) * SPACING, 0.55, 0.0), turn, f"quad_uv{turn:g}"))
    for column, (metallic, roughness, spec_trans, anisotropic) in enumerate(SPHERES):
        label = f"m{metallic:g}_r{roughness:g}" + (f"_t{spec_trans:g}" if spec_trans else "") + f"_a{anisotropic:g}"
        material = Principled(
            f"anisotropic_{label}",
            METAL_COLOR,
            metallic=metallic,
            roughness=roughness,
            spec_trans=spec_trans,
            anisotropic=anisotropic,
        )
        position = ((column - 1) * SPACING, -0.55, 0.0)
        shapes.append(make_icosphere(position, (0, 0, 0), RADIUS, 3, material, f"sphere_{label}", smooth=True))
    return Scene(shapes, Camera.looking_at((0.0, 0.0, 3.5), (0.0, 0.0, 0.0), vfov_degrees=50.0))
