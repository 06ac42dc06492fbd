"""Vertex-coloured triangles under a small lamp (glTF's COLOR_0 multiplying the base colour), for the
Mitsuba 3 reference of vertex colours, which the export reads through a `mesh_attribute` texture
(`mitsuba_scene.vertex_colored`):

- a diffuse backdrop of two triangles whose colours are a function of the vertex (one colour per
  vertex, ramping red to green across and darker upwards), times a warm material colour;
- a glossy triangle standing on the floor, its corners red, green and blue (one per corner: a
  rotated or mirrored corner order moves them);
- a diffuse quad whose two triangles have colours of their own at the shared corners (per corner,
  not per vertex: a hard edge along the diagonal, blue above and yellow below);
- a grey floor without colours: white in a scene that has them.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Diffuse, Glossy, Scene, Shape, make_plane
from .stage import backdrop, floor, square_lamp

FLOOR_SIDE = 6.0
BACKDROP_Z = 1.5
BACKDROP_SIZE = (3.0, 2.0)
TRIANGLE_CORNERS = np.array([[[-1.1, 0.0, 0.2], [-0.1, 0.0, 0.6], [-0.6, 1.1, 0.4]]], np.float32)
TRIANGLE_ROUGHNESS = 0.3
# red, green and blue, not pure, so that every channel has light to carry
CORNER_RGB = np.array([[0.9, 0.15, 0.1], [0.1, 0.85, 0.2], [0.15, 0.2, 0.9]], np.float32)
QUAD_CENTRE = (0.7, 0.5, 0.5)
QUAD_SIDE = 0.8
DIAGONAL_RGB = {0: (0.2, 0.3, 0.95), 1: (0.95, 0.85, 0.1)}  # by triangle
LAMP_CENTRE = (0.0, 2.5, -0.3)
LAMP_SIDE = 0.5
LAMP_EMITTANCE = 40.0


def rgba(rgb: np.ndarray) -> np.ndarray:
    """RGB rows (..., 3) with alpha 1."""
    return np.concatenate([rgb, np.ones((*rgb.shape[:-1], 1), np.float32)], axis=-1)


def vertex_colored_triangles() -> Scene:
    wall = backdrop(Diffuse("wall", color=(0.9, 0.8, 0.7)), "wall", BACKDROP_Z, BACKDROP_SIZE)
    corners = wall.world_vertices
    across = (corners[..., 0] - corners[..., 0].min()) / np.ptp(corners[..., 0])
    up = corners[..., 1] / corners[..., 1].max()
    wall.colors = rgba(np.stack([1.0 - across, across, 0.5 * np.ones_like(across)], -1) * (1.0 - 0.6 * up)[..., None])
    metal = Glossy("metal", color=(0.95, 0.9, 0.8), roughness=TRIANGLE_ROUGHNESS)
    triangle = Shape("triangle", TRIANGLE_CORNERS, metal, colors=rgba(CORNER_RGB)[None])
    # facing the camera (-z), as the backdrop
    quad = make_plane(QUAD_CENTRE, (-np.pi / 2, 0, 0), (QUAD_SIDE, QUAD_SIDE), Diffuse("quad", (0.8, 0.8, 0.8)), "quad")
    quad.colors = rgba(np.array([[DIAGONAL_RGB[index]] * 3 for index in range(2)], np.float32))
    shapes = [
        floor(Diffuse("floor", color=(0.6, 0.6, 0.6)), FLOOR_SIDE),
        wall,
        triangle,
        quad,
        square_lamp(LAMP_CENTRE, LAMP_SIDE, LAMP_EMITTANCE),
    ]
    return Scene(shapes, Camera.looking_at((0.0, 1.0, -3.2), (0.0, 0.6, 0.5), vfov_degrees=45.0))
