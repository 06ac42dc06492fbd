"""Sliver and degenerate triangles: a wall made of a fan of needle-thin triangles, a floor of
long thin strips, zero-area triangles mixed in, and a bright red lamp hidden behind the wall.

Red anywhere on the wall or floor is light that leaked through a shared edge: an intersection
test that is not watertight lets rays slip between slivers. Zero-area triangles (repeated or
collinear corners) are dropped on the host with a DegenerateTrianglesWarning; the needles (area
near f32's resolution, but not zero) stay and must neither be hit wrongly nor make a NaN normal.
"""

from __future__ import annotations

import math

import numpy as np

from ..scene import Camera, Diffuse, Emitter, Scene, Shape, make_plane

WALL_HALF_SIZE = 1.2
WALL_Z = 1.0
FAN_TRIANGLES_PER_EDGE = 150
FLOOR_STRIPS = 1500
FLOOR_NEAR_Z = -2.5
NEEDLES = 50
# A needle's width: a few float32 ulps at coordinates near 1, so its area is tiny but not zero.
NEEDLE_WIDTH = 4.0 * float(np.finfo(np.float32).eps)


def _fan_wall() -> np.ndarray:
    """The square wall z = WALL_Z as a fan around its lower left corner, with zero-area triangles:
    a repeated corner, and three corners on the (axis-parallel) top edge."""
    h = WALL_HALF_SIZE
    top = np.linspace(-h, h, FAN_TRIANGLES_PER_EDGE + 1)
    rim = np.concatenate(
        [np.stack([top, np.full_like(top, h)], axis=1), np.stack([np.full_like(top, h), -top], axis=1)[1:]]
    )
    rim = np.concatenate([rim, np.full((len(rim), 1), WALL_Z)], axis=1)
    corner = np.broadcast_to([-h, -h, WALL_Z], rim[:-1].shape)
    fan = np.stack([corner, rim[1:], rim[:-1]], axis=1)
    repeated = np.stack([corner[:10], corner[:10], rim[:10]], axis=1)
    collinear = np.stack([rim[:10], rim[1:11], rim[2:12]], axis=1)
    return np.concatenate([fan, repeated, collinear])


def _strip_floor() -> np.ndarray:
    """The floor y = -WALL_HALF_SIZE under the wall as long strips, each two thin triangles."""
    h = WALL_HALF_SIZE
    x = np.linspace(-h, h, FLOOR_STRIPS + 1)
    near, far = np.full(FLOOR_STRIPS, FLOOR_NEAR_Z), np.full(FLOOR_STRIPS, WALL_Z)
    y = np.full(FLOOR_STRIPS, -h)

    def corner(xs, zs):
        return np.stack([xs, y, zs], axis=1)

    a, b, c, d = corner(x[:-1], near), corner(x[1:], near), corner(x[1:], far), corner(x[:-1], far)
    return np.concatenate([np.stack([a, c, b], axis=1), np.stack([a, d, c], axis=1)])


def _needles() -> np.ndarray:
    """Needles standing on the floor in front of the wall, NEEDLE_WIDTH wide at the base."""
    x = np.linspace(-0.9 * WALL_HALF_SIZE, 0.9 * WALL_HALF_SIZE, NEEDLES)
    base = np.stack([x, np.full(NEEDLES, -WALL_HALF_SIZE), np.full(NEEDLES, 0.5 * WALL_Z)], axis=1)
    return np.stack([base, base + [NEEDLE_WIDTH, 0.0, 0.0], base + [0.5 * NEEDLE_WIDTH, 1.5, 0.0]], axis=1)


def slivers() -> Scene:
    white = Diffuse("white", color=(0.75, 0.75, 0.75))
    sand = Diffuse("sand", color=(0.6, 0.55, 0.45))
    lamp = Emitter("lamp", color=(1.0, 0.95, 0.9), emittance=10.0)
    hidden = Emitter("hidden_red", color=(1.0, 0.02, 0.02), emittance=30.0)
    shapes = [
        Shape("fan_wall", _fan_wall(), white),
        Shape("strip_floor", _strip_floor(), sand),
        Shape("needles", _needles(), white),
        make_plane((0.0, 1.6, -1.0), (0, 0, 0), (0.8, 0.8), lamp, "lamp"),
        # behind the wall, facing it, smaller than it: seen only through leaks
        make_plane((0.0, 0.0, WALL_Z + 0.25), (-math.pi / 2, 0, 0), (1.4, 1.4), hidden, "hidden_lamp"),
    ]
    return Scene(shapes, Camera.looking_at((0.0, 0.0, -2.5), (0.0, -0.1, WALL_Z), vfov_degrees=45.0))
