"""Scenes the tests build: small scenes with closed-form images, a textured square, random triangle
soups and rays around them, and a soup whose binned-SAH tree is far deeper than logarithmic."""

from __future__ import annotations

import numpy as np

from wgputrace import Camera, Diffuse, Emitter, Glass, Scene, make_box, make_icosphere

ENCLOSURE_RADIANCE = (0.8, 1.6, 2.4)
# The square |x|, |y| <= 1 in z = 0, corner by corner around it, with glTF texture coordinates:
# uv (0, 0) at (-1, 1, 0), u along +x, v along -y (seen from -z: the top-left, right and down).
SQUARE_CORNERS = np.array([(-1, 1, 0), (1, 1, 0), (1, -1, 0), (-1, -1, 0)], np.float32)
SQUARE_UVS = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], np.float32)
# Triangle soups live in [-1, 1]^3; corners scatter around a centre with this standard deviation.
TRIANGLE_SIZE = 0.08


def inside_emitter(*inner_shapes) -> Scene:
    """The camera and `inner_shapes` inside a closed box that emits ENCLOSURE_RADIANCE everywhere."""
    light = Emitter("enclosure", color=ENCLOSURE_RADIANCE, emittance=1.0)
    enclosure = make_box((0, 0, 0), (0.1, 0.2, 0.3), (6, 6, 6), light, "enclosure")
    camera = Camera(position=(0, 0, -2), forward=(0, 0, 1), up=(0, 1, 0), vfov_degrees=40.0)
    return Scene([enclosure, *inner_shapes], camera)


def diffuse_sphere_in_emitter(albedo) -> Scene:
    return inside_emitter(make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 2, Diffuse("ball", color=albedo), "ball"))


def glass_sphere_in_emitter(ior: float = 1.5) -> Scene:
    return inside_emitter(make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 2, Glass("ball", color=(1, 1, 1), ior=ior), "ball"))


def uv_square(normal_z: int) -> tuple[np.ndarray, np.ndarray]:
    """The square as two (2, 3, 3) triangles wound so that their normal is (0, 0, normal_z), -1 or 1,
    and their corners' (2, 3, 2) texture coordinates."""
    faces = np.array([[0, 1, 2], [0, 2, 3]]) if normal_z < 0 else np.array([[0, 2, 1], [0, 3, 2]])
    return SQUARE_CORNERS[faces], SQUARE_UVS[faces]


def random_soup(rng: np.random.Generator, count: int, size: float = TRIANGLE_SIZE) -> np.ndarray:
    """(count, 3, 3) float32 triangles: centres uniform in [-1, 1]^3, corners normal around them."""
    centres = rng.uniform(-1.0, 1.0, size=(count, 1, 3))
    return (centres + rng.normal(scale=size, size=(count, 3, 3))).astype(np.float32)


def random_rays(rng: np.random.Generator, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Origins around a random soup; most rays aim into it, a quarter go anywhere."""
    origins = rng.uniform(-3.0, 3.0, size=(count, 3))
    directions = rng.uniform(-1.0, 1.0, size=(count, 3)) - origins
    wild = rng.random(count) < 0.25
    directions[wild] = rng.normal(size=(wild.sum(), 3))
    return origins, directions


def geometric_peel_scene(per_axis: int = 120, at_origin: int = 1000) -> np.ndarray:
    """Tiny triangles at 2^-k along each axis plus a cluster at the origin.

    Binned SAH peels only a few of them off per level, so the natural depth is far from logarithmic.
    """
    centres = np.zeros((3 * per_axis + at_origin, 3))
    for axis in range(3):
        centres[axis * per_axis : (axis + 1) * per_axis, axis] = 0.5 ** np.arange(per_axis)
    size = np.maximum(np.abs(centres).max(axis=1), 1e-36) * 1e-2
    vertices = np.repeat(centres[:, None, :], 3, axis=1)
    vertices[:, 1, 0] += size
    vertices[:, 2, 1] += size
    return vertices.astype(np.float32)
