"""An alpha-cut quad casting a shadow: a Principled MASK quad striped by its base colour
texture's alpha, between a small lamp and a white wall, the camera seeing the quad and its striped
shadow. The cut-out decides the camera's rays and the shadow rays alike (`surface_blocks`).
`alpha_blend` is the same with a BLEND quad whose alpha ramps across it: stochastic transparency
for every ray, whose expectation Mitsuba's `mask` renders (Principled.mitsuba_opacity).

The stripes are two texels wide with alpha 0 or 1: the bilinear alpha the shader thresholds at 0.5
crosses it on texel boundaries, so the cut-out is the thresholded texels looked up nearest, as the
Mitsuba export's `mask` opacity is (Principled.mitsuba_bsdf).
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Diffuse, Emitter, Principled, Scene, Shape, Texture

STRIPE_TEXELS = 2
TEXTURE_TEXELS = 8
QUAD_HALF_SIZE = 0.5
WALL_HALF_SIZE = 3.0
WALL_Z = 1.5
LAMP_CENTRE = (0.8, 0.5, -1.5)
LAMP_HALF_SIZE = 0.15
LAMP_EMITTANCE = 100.0


def stripes_texture() -> Texture:
    """sRGB orange, opaque in columns of STRIPE_TEXELS alternating with transparent ones."""
    columns = np.indices((TEXTURE_TEXELS, TEXTURE_TEXELS))[1]
    pixels = np.empty((TEXTURE_TEXELS, TEXTURE_TEXELS, 4), np.uint8)
    pixels[..., :3] = (230, 140, 40)
    pixels[..., 3] = np.where((columns // STRIPE_TEXELS) % 2 == 0, 255, 0)
    return Texture(pixels, name="stripes")


def square(centre, half_size: float) -> np.ndarray:
    """Two triangles of a square in the plane z = centre's z, facing -z, uv (0, 0) at the top-left
    as a camera looking along +z sees it (image right is -x)."""
    x, y, z = centre
    h = half_size
    corners = np.array([(x + h, y + h, z), (x - h, y + h, z), (x - h, y - h, z), (x + h, y - h, z)], np.float32)
    return corners[np.array([[0, 2, 1], [0, 3, 2]])]


def ramp_texture() -> Texture:
    """sRGB blue, its alpha rising across the columns from 1/8 to 1 (rows alike)."""
    pixels = np.empty((TEXTURE_TEXELS, TEXTURE_TEXELS, 4), np.uint8)
    pixels[..., :3] = (60, 120, 220)
    pixels[..., 3] = np.round(255 * (np.arange(TEXTURE_TEXELS) + 1) / TEXTURE_TEXELS).astype(np.uint8)
    return Texture(pixels, name="ramp")


def alpha_cutout() -> Scene:
    return leaf_before_wall(Principled("leaf", roughness=0.8, base_color_texture=stripes_texture(), alpha_mode="MASK"))


def alpha_blend() -> Scene:
    return leaf_before_wall(Principled("veil", roughness=0.8, base_color_texture=ramp_texture(), alpha_mode="BLEND"))


def leaf_before_wall(leaf: Principled) -> Scene:
    """The quad of material `leaf` between the lamp and the wall."""
    uv = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)], np.float32)[np.array([[0, 2, 1], [0, 3, 2]])]
    lamp = Emitter("lamp", color=(1.0, 0.95, 0.9), emittance=LAMP_EMITTANCE)
    shapes = [
        Shape("wall", square((0.0, 0.0, WALL_Z), WALL_HALF_SIZE), Diffuse("wall", (0.8, 0.8, 0.8))),
        Shape("leaf", square((0.0, 0.0, 0.0), QUAD_HALF_SIZE), leaf, uvs=uv),
        # facing +z, towards the quad and the wall
        Shape("lamp", square(LAMP_CENTRE, LAMP_HALF_SIZE)[:, [0, 2, 1]], lamp),
    ]
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -3.0), (0.0, 0.0, 0.0), vfov_degrees=45.0))
