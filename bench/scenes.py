"""The scenes several benchmarks render (a wavy height field of any triangle count, lit from above)
and rays through a camera's pixel centres for traversal checks against other engines."""

from __future__ import annotations

import math

import numpy as np

from wgputrace import Camera, Diffuse, Emitter, Scene, Shape, make_plane

# The sheet spans [-1, 1]^2 with heights within +-0.1; from this height a 50-degree view sees a
# square of half-width 0.75 at most: the sheet fills the image at every triangle count.
SHEET_CAMERA_HEIGHT = 1.5
SHEET_VFOV_DEGREES = 50.0
SHEET_LAMP = {"height": 3.0, "size": 1.0, "emittance": 20.0}
# The height field of bench.big_mesh and bench.bvh_build_baseline: 2 x 708^2 = 1,002,528 triangles.
BIG_MESH_CELLS = 708
# The counts the sheet is rendered (bench.scaling) and built (bench.bvh_build) at.
TRIANGLE_COUNTS = (10, 100, 1_000, 10_000, 100_000, 1_000_000)


def height_field(cells: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertices ((cells + 1)^2, 3) and faces (2 cells^2, 3) of a wavy sheet over [-1, 1]^2, facing +y."""
    x, z = np.meshgrid(np.linspace(-1, 1, cells + 1), np.linspace(-1, 1, cells + 1), indexing="ij")
    y = 0.1 * np.sin(9 * x) * np.cos(7 * z)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    a = (i * (cells + 1) + j).ravel()
    b, c, d = a + 1, a + cells + 1, a + cells + 2
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    return vertices, faces


def sheet_scene(triangles: int) -> Scene:
    """The height field with about `triangles` triangles (2 cells^2) seen from straight above, lit
    by a square lamp above the camera and out of view: it fills the image at every count."""
    cells = max(1, round(math.sqrt(triangles / 2)))
    vertices, faces = height_field(cells)
    sheet = Shape("sheet", vertices[faces], Diffuse("sheet", color=(0.7, 0.7, 0.7)))
    lamp = make_plane(
        (0, SHEET_LAMP["height"], 0),
        (np.pi, 0, 0),
        (SHEET_LAMP["size"], SHEET_LAMP["size"]),
        Emitter("lamp", emittance=SHEET_LAMP["emittance"]),
        "lamp",
    )
    # looking straight down, with +z as the picture's up (an exactly vertical up vector would be degenerate)
    camera = Camera.looking_at((0, SHEET_CAMERA_HEIGHT, -1e-3), (0, 0, 0), vfov_degrees=SHEET_VFOV_DEGREES)
    return Scene([sheet, lamp], camera)


def pixel_centre_rays(camera: Camera, width: int, height: int, dtype=np.float32) -> tuple[np.ndarray, np.ndarray]:
    """(origins, unit directions), (width * height, 3), row 0 at the top: the shader's `camera_ray`
    with the jitter at the pixel centre."""
    right, up, forward = camera.image_plane(width, height)
    x = (np.arange(width) + 0.5) / width * 2.0 - 1.0
    y = (np.arange(height) + 0.5) / height * 2.0 - 1.0
    directions = forward + x[None, :, None] * right - y[:, None, None] * up
    directions = (directions / np.linalg.norm(directions, axis=-1, keepdims=True)).reshape(-1, 3)
    origins = np.broadcast_to(np.asarray(camera.position, np.float64), directions.shape)
    return origins.astype(dtype), directions.astype(dtype)
