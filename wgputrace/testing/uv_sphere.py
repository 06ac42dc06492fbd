"""A UV sphere as a modelling tool exports one: rings of vertices shared by the triangles around them,
the seam's doubled (u = 0 and u = 1), its texture coordinates and normals per vertex. The smooth,
textured mesh whose GPU memory per triangle `bench.attribute_memory` and the tests measure."""

from __future__ import annotations

import numpy as np

from wgputrace import Camera, DirectionalLight, Principled, Scene, Shape, Texture


def uv_sphere(segments: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A unit sphere's vertex positions (v, 3), normals (v, 3), texture coordinates (v, 2) float32 and
    triangles (n, 3) indexing them: `segments` rings of 2 x segments slices, 4 s^2 - 4 s triangles
    (the poles' zero-area ones left out, as Scene.arrays would drop them)."""
    v = np.linspace(0.0, 1.0, segments + 1)
    u = np.linspace(0.0, 1.0, 2 * segments + 1)
    uu, vv = np.meshgrid(u, v)
    theta, phi = 2 * np.pi * uu, np.pi * vv
    normals = np.stack([np.sin(phi) * np.cos(theta), np.cos(phi), np.sin(phi) * np.sin(theta)], -1).reshape(-1, 3)
    uvs = np.stack([uu, vv], -1).reshape(-1, 2)
    row, column = np.meshgrid(np.arange(segments), np.arange(2 * segments), indexing="ij")
    a = row * (2 * segments + 1) + column
    b, c, d = a + 2 * segments + 1, a + 2 * segments + 2, a + 1
    # the first ring's (a, d, b) and the last ring's (d, c, b) have two corners at a pole: no area
    triangles = np.concatenate([np.stack([a, d, b], -1)[1:], np.stack([d, c, b], -1)[:-1]]).reshape(-1, 3)
    normals = normals.astype(np.float32)
    return normals, normals, uvs.astype(np.float32), triangles


def textured_sphere(segments: int) -> Scene:
    """`uv_sphere` as one smooth Shape (its corners gathered through the triangles, as a loader
    flattens an index buffer) with a base colour texture and a normal map, under a sun."""
    positions, normals, uvs, triangles = uv_sphere(segments)
    checks = np.indices((8, 8)).sum(axis=0) % 2
    base = Texture(np.where(checks[..., None], 200, 60).astype(np.uint8).repeat(3, axis=-1), name="checks")
    bumps = Texture(np.full((4, 4, 3), (0.6, 0.5, 0.9), np.float32), srgb=False, name="tilt")
    material = Principled("sphere", base_color=(1.0, 1.0, 1.0), base_color_texture=base, normal_texture=bumps)
    shape = Shape("sphere", positions[triangles], material, normals=normals[triangles], uvs=uvs[triangles])
    scene = Scene([shape], Camera.looking_at((0.0, 0.5, -3.0), (0, 0, 0), vfov_degrees=45.0))
    scene.add_light(DirectionalLight((0.4, -0.6, 0.7), 3.0))
    return scene
