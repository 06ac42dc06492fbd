"""Textured quads: the Principled material's textures in the emitting room, made here (no files).

The left quad's base colour is an 8-bit sRGB checkerboard whose top-left texel block is red (the
marked corner: a flipped or transposed lookup moves it), its coordinates running past [0, 1] so it
repeats. The right quad's metallic-roughness texture ramps roughness (G) across it and switches
metallic (B) in stripes, mirrored past [0, 1] and turned by a KHR_texture_transform. Errors in
orientation, sRGB decoding, wrap modes, transforms or filtering move or recolour texels.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Principled, Scene, Shape, Texture, TextureTransform
from .emitting_room import emitting_room

ROOM_HALF_SIZE = 4.0
ROOM_CELLS = 8
CHECKER_TEXELS = 8
MARK_TEXELS = 2
QUAD_HALF_SIZE = 0.7
# image right is -x for a camera looking along +z
QUAD_CENTRES = ((0.8, 0.0, 0.0), (-0.8, 0.0, 0.0))


def checker_texture() -> Texture:
    """sRGB checkerboard of a light and a dark blue-grey, its top-left block red."""
    rows, columns = np.indices((CHECKER_TEXELS, CHECKER_TEXELS))
    pixels = np.where(((rows + columns) % 2 == 0)[..., None], (230, 220, 200), (40, 60, 90)).astype(np.uint8)
    pixels[:MARK_TEXELS, :MARK_TEXELS] = (220, 30, 20)
    return Texture(pixels, name="checker")


def metallic_roughness_texture() -> Texture:
    """Linear: G (roughness) ramps 0.05 to 1 along u, B (metallic) alternates 0 and 1 in rows of 4."""
    rows, columns = np.indices((16, 16))
    texels = np.zeros((16, 16, 3), np.float32)
    texels[..., 1] = 0.05 + 0.95 * columns / 15
    texels[..., 2] = (rows // 4) % 2
    transform = TextureTransform(offset=(0.1, -0.2), rotation=0.4, scale=(1.3, 0.9))
    return Texture(texels, srgb=False, wrap_s="mirror", wrap_t="mirror", name="metallic_roughness", transform=transform)


def quad(centre, name: str, material: Principled, uv_range: tuple[float, float]) -> Shape:
    """A square facing the camera (-z), uv (low, low) at its top-left corner as the camera sees it."""
    x, y, z = centre
    h = QUAD_HALF_SIZE
    # top-left, top-right, bottom-right, bottom-left seen from -z (image right is -x)
    corners = np.array([(x + h, y + h, z), (x - h, y + h, z), (x - h, y - h, z), (x + h, y - h, z)], np.float32)
    low, high = uv_range
    uv = np.array([(low, low), (high, low), (high, high), (low, high)], np.float32)
    faces = np.array([[0, 2, 1], [0, 3, 2]])
    return Shape(name, corners[faces], material, uvs=uv[faces])


def textured_quads() -> Scene:
    shapes = emitting_room(ROOM_HALF_SIZE, ROOM_CELLS)
    checker = Principled("checker", (1.0, 1.0, 1.0), roughness=0.7, base_color_texture=checker_texture())
    shapes.append(quad(QUAD_CENTRES[0], "checker_quad", checker, (-0.25, 1.25)))
    ramp = Principled(
        "ramp", (0.9, 0.6, 0.3), metallic=1.0, roughness=1.0, metallic_roughness_texture=metallic_roughness_texture()
    )
    shapes.append(quad(QUAD_CENTRES[1], "ramp_quad", ramp, (-0.5, 1.5)))
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -3.0), (0.0, 0.0, 0.0), vfov_degrees=45.0))
