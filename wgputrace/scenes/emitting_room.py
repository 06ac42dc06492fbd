"""A closed room whose walls are all light: checkerboards of emitters, a different hue per wall.

Scenes lit by it need no lamp, and a camera ray that leaves through glass or off a mirror ends
on an emitter at once: the image depends on where refracted and reflected rays go (a wrong
direction lands on another cell or another hue) and on how much they carry, with little noise.
"""

from __future__ import annotations

import numpy as np

from ..scene import Emitter, Shape

# Radiance of each wall's bright cells, by the axis and side of the wall: distinct hues, so a
# reflection or refraction that goes the wrong way shows the wrong colour.
WALL_HUES = {
    (0, +1): (1.0, 0.35, 0.3),
    (0, -1): (0.35, 1.0, 0.35),
    (1, +1): (1.0, 1.0, 1.0),
    (1, -1): (0.5, 0.4, 0.3),
    (2, +1): (0.3, 0.5, 1.0),
    (2, -1): (1.0, 0.85, 0.3),
}
# The dim cells of a wall: its hue times this.
DIM_CELL_SCALE = 0.2


def _wall_cells(axis: int, side: int, half_size: float, cells: int) -> tuple[np.ndarray, np.ndarray]:
    """The wall's cells as triangles (2 per cell) wound to face the room's centre, and which are bright."""
    edges = np.linspace(-half_size, half_size, cells + 1)
    i, j = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    i, j = i.ravel(), j.ravel()
    u_axis, v_axis = [a for a in range(3) if a != axis]
    quads = np.zeros((len(i), 4, 3))
    quads[:, :, axis] = side * half_size
    for corner, (di, dj) in enumerate(((0, 0), (1, 0), (1, 1), (0, 1))):
        quads[:, corner, u_axis] = edges[i + di]
        quads[:, corner, v_axis] = edges[j + dj]
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    normal = np.cross(triangles[0, 1] - triangles[0, 0], triangles[0, 2] - triangles[0, 0])
    if normal[axis] * side > 0:  # pointing out of the room: turn every triangle round
        triangles = triangles[:, [0, 2, 1]]
    bright = np.tile((i + j) % 2 == 0, 2)
    return triangles, bright


def emitting_room(half_size: float, cells: int) -> list[Shape]:
    """Six walls of `cells` x `cells` emitting squares around the origin, from -half_size to
    half_size on every axis; two shapes (bright cells, dim cells) per wall."""
    shapes = []
    for (axis, side), hue in WALL_HUES.items():
        triangles, bright = _wall_cells(axis, side, half_size, cells)
        name = f"{'xyz'[axis]}{'+' if side > 0 else '-'}"
        for label, mask, scale in (("bright", bright, 1.0), ("dim", ~bright, DIM_CELL_SCALE)):
            light = Emitter(f"wall_{name}_{label}", color=hue, emittance=scale)
            shapes.append(Shape(f"wall_{name}_{label}", triangles[mask], light))
    return shapes
