"""A street at night lit by 1,065 windows and 24 street lamps, and nothing else: the scene where a
light chosen by power is almost never the one that matters.

Two rows of buildings face each other across a street. Each building's facade is a grid of wall
and windows, about two thirds of the windows lit in four hues and brightnesses (a fixed seed
chooses which); lamps hang over both kerbs, brighter and smaller. The power table draws every
window of a hue alike, most of them far away or facing away from the point being shaded, so
next-event estimation's samples mostly land on lights that add little; resampling by contribution
(the restir integrator) finds the near lamp and the windows across the street. Glossy tarmac
reflects them, and parked boxes cast shadows that only a visibility test gets right.

A window is a cell of its facade's grid, not a quad in front of a wall: an emitter shines from
both sides, and a wall a hair behind it would trap light that leaks out by the width of the gap
(which Mitsuba's export of two-sided emitters narrows: `EMITTER_BACK_OFFSET_RELATIVE`). Here the
back of each window shines into its closed building.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Diffuse, Emitter, Glossy, Material, Scene, Shape, make_box, make_plane

STREET_HALF_WIDTH = 4.0  # the facades stand at x = +-4
BUILDINGS_PER_SIDE = 8
BUILDING_LENGTH = 5.0  # along z, with a gap of BUILDING_GAP between buildings
BUILDING_GAP = 1.0
BUILDING_DEPTH = 6.0
BUILDING_HEIGHTS = (12.0, 26.0)  # uniform between
WINDOW_COLUMNS = 8  # per building
WINDOW_BOTTOM = 1.2  # the first floor's sill; a floor every FLOOR_HEIGHT above it
FLOOR_HEIGHT = 1.4
WINDOW_SIZE = (0.45, 0.8)  # width along the facade, height
LIT_FRACTION = 0.7
LAMPS_PER_SIDE = 12
LAMP_HEIGHT = 4.5
LAMP_SIZE = 0.25  # a square facing down
LAMP_RADIANCE = (60.0, 38.0, 14.0)
# the lit windows' radiance: warm, cool, white and a dim warm; each lit window takes one at random
WINDOW_HUES = (
    ("warm", (2.4, 1.6, 0.8)),
    ("cool", (0.9, 1.3, 2.2)),
    ("white", (2.0, 2.0, 2.0)),
    ("dim", (0.6, 0.4, 0.25)),
)
SEED = 20261203


def _quad(x: float, y: tuple[float, float], z: tuple[float, float], facing: float) -> np.ndarray:
    """Two triangles of the rectangle y x z in the plane at x, wound to face +x (facing 1) or -x."""
    (y0, y1), (z0, z1) = y, z
    corners = np.array([[x, y0, z0], [x, y1, z0], [x, y1, z1], [x, y0, z1]])
    triangles = np.stack([corners[[0, 1, 2]], corners[[0, 2, 3]]])
    return triangles if facing > 0 else triangles[:, [0, 2, 1]]


def _facade(x: float, facing: float, z_start: float, height: float, rng: np.random.Generator) -> tuple[list, list]:
    """One facade's grid at x: its wall cells' triangles, and its lit windows as (hue, triangles)
    (unlit windows are wall)."""
    width, tall = WINDOW_SIZE
    spacing = BUILDING_LENGTH / WINDOW_COLUMNS
    left_edges = [z_start + (column + 0.5) * spacing - width / 2 for column in range(WINDOW_COLUMNS)]
    window_z = [(z0, z0 + width) for z0 in left_edges]
    floors = int((height - 0.3 - tall - WINDOW_BOTTOM) // FLOOR_HEIGHT) + 1
    window_y = [
        (WINDOW_BOTTOM + row * FLOOR_HEIGHT, WINDOW_BOTTOM + row * FLOOR_HEIGHT + tall) for row in range(floors)
    ]
    z_edges = [z_start, *(z for pair in window_z for z in pair), z_start + BUILDING_LENGTH]
    y_edges = [0.0, *(y for pair in window_y for y in pair), height]
    wall, windows = [], []
    for i in range(len(y_edges) - 1):
        for j in range(len(z_edges) - 1):
            cell = _quad(x, (y_edges[i], y_edges[i + 1]), (z_edges[j], z_edges[j + 1]), facing)
            # odd intervals of both edge lists are windows
            if i % 2 == 1 and j % 2 == 1 and rng.random() < LIT_FRACTION:
                windows.append((int(rng.integers(len(WINDOW_HUES))), cell))
            else:
                wall.append(cell)
    return wall, windows


def _building(side: float, z_start: float, height: float, material: Material, name: str) -> Shape:
    """A box of the building's size without its face towards the street (its facade's grid)."""
    centre = (side * (STREET_HALF_WIDTH + BUILDING_DEPTH / 2), height / 2, z_start + BUILDING_LENGTH / 2)
    box = make_box(centre, (0, 0, 0), (BUILDING_DEPTH, height, BUILDING_LENGTH), material, name)
    triangles = box.world_vertices.astype(np.float64)
    towards_street = np.abs(triangles[:, :, 0] - side * STREET_HALF_WIDTH).max(axis=1) < 1e-6
    return Shape(name, triangles[~towards_street], material)


def night_street() -> Scene:
    rng = np.random.default_rng(SEED)
    facade = Diffuse("facade", color=(0.45, 0.42, 0.4))
    tarmac = Glossy("tarmac", color=(0.25, 0.25, 0.27), roughness=0.35)
    shapes = [make_plane((0.0, 0.0, 20.0), (0, 0, 0), (40.0, 60.0), tarmac, "street")]
    windows: list[list[np.ndarray]] = [[] for _ in WINDOW_HUES]
    for side in (-1.0, 1.0):
        for index in range(BUILDINGS_PER_SIDE):
            z_start = index * (BUILDING_LENGTH + BUILDING_GAP) - 4.0
            height = float(rng.uniform(*BUILDING_HEIGHTS))
            name = f"building_{'left' if side < 0 else 'right'}_{index}"
            shapes.append(_building(side, z_start, height, facade, name))
            wall, lit = _facade(side * STREET_HALF_WIDTH, -side, z_start, height, rng)
            shapes.append(Shape(f"{name}_facade", np.concatenate(wall), facade))
            for hue, triangles in lit:
                windows[hue].append(triangles)
    for (name, radiance), triangles in zip(WINDOW_HUES, windows, strict=True):
        shapes.append(Shape(f"windows_{name}", np.concatenate(triangles), Emitter(f"window_{name}", color=radiance)))
    lamp = Emitter("street_lamp", color=LAMP_RADIANCE)
    lamp_z = np.linspace(-3.0, BUILDINGS_PER_SIDE * (BUILDING_LENGTH + BUILDING_GAP) - 6.0, LAMPS_PER_SIDE)
    for side in (-1.0, 1.0):
        for index, z in enumerate(lamp_z):
            # turned half a turn about x: the square faces down
            position = (side * (STREET_HALF_WIDTH - 0.8), LAMP_HEIGHT, float(z))
            shapes.append(
                make_plane(position, (np.pi, 0, 0), (LAMP_SIZE, LAMP_SIZE), lamp, f"lamp_{side:+.0f}_{index}")
            )
    parked = Diffuse("parked", color=(0.5, 0.12, 0.1))
    for index, (x, z) in enumerate(((-2.6, 4.0), (2.7, 9.0), (-2.5, 16.0), (2.6, 22.0))):
        shapes.append(make_box((x, 0.6, z), (0, 0.1 * index, 0), (1.8, 1.2, 4.0), parked, f"parked_{index}"))
    camera = Camera.looking_at((0.6, 1.7, -7.0), (-0.3, 4.0, 25.0), vfov_degrees=55.0)
    return Scene(shapes, camera)
