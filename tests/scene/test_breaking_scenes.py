"""The scenes that break path tracers (the built-in `door_ajar`, `caustic` and `glossy_through_glossy`)
have the geometry they exist for, checked with a numpy segment test."""

from __future__ import annotations

import numpy as np

from wgputrace.scenes import scene_by_name
from wgputrace.scenes.caustic import SPHERE_CENTRE, caustic_centre, caustic_mask
from wgputrace.scenes.door_ajar import DIVIDER_Z, HALF_WIDTH, HEIGHT, ROOM_FRONT, WALL_THICKNESS

SEED = 20261202
POINTS = 64
SIZE = 64


def blocked(starts: np.ndarray, ends: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Per segment (start, end), whether it crosses any triangle strictly between its ends
    (Moller-Trumbore on every pair, in float64)."""
    direction = (ends - starts)[:, None, :]
    v0, e1, e2 = (
        triangles[None, :, 0],
        triangles[None, :, 1] - triangles[None, :, 0],
        triangles[None, :, 2] - triangles[None, :, 0],
    )
    p = np.cross(direction, e2)
    determinant = np.sum(e1 * p, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = 1.0 / determinant
        s = starts[:, None, :] - v0
        u = np.sum(s * p, axis=-1) * inverse
        q = np.cross(s, e1)
        v = np.sum(direction * q, axis=-1) * inverse
        t = np.sum(e2 * q, axis=-1) * inverse
    hit = (np.abs(determinant) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-6) & (t < 1 - 1e-6)
    return hit.any(axis=1)


def walls_and_door(scene) -> np.ndarray:
    """The door_ajar scene's walls and door, float64: what must block the lamp (the furniture
    is left out, so it cannot be what blocks)."""
    kept = [
        s.world_vertices for s in scene.shapes if s.name.startswith(("floor", "ceiling", "wall", "divider", "door"))
    ]
    return np.concatenate(kept).astype(np.float64)


def shape_triangles(scene, name: str) -> np.ndarray:
    (shape,) = [shape for shape in scene.shapes if shape.name == name]
    return shape.world_vertices.astype(np.float64)


def points_on(triangles: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """`count` random points on the triangles (uniform within each, triangles chosen uniformly)."""
    chosen = triangles[rng.integers(len(triangles), size=count)]
    u, v = rng.random((2, count, 1))
    flip = (u + v) > 1
    u, v = np.where(flip, 1 - u, u), np.where(flip, 1 - v, v)
    return chosen[:, 0] + u * (chosen[:, 1] - chosen[:, 0]) + v * (chosen[:, 2] - chosen[:, 0])


def camera_room_points(count: int, rng: np.random.Generator) -> np.ndarray:
    """Random points inside the camera's room, clear of its walls."""
    margin = 0.05
    low = (-HALF_WIDTH + margin, margin, ROOM_FRONT + margin)
    high = (
        HALF_WIDTH - margin,
        HEIGHT - margin,
        DIVIDER_Z - WALL_THICKNESS,
    )
    return rng.uniform(low, high, size=(count, 3))


def test_door_ajar_lamp_lights_the_camera_room_only_indirectly():
    rng = np.random.default_rng(SEED)
    scene = scene_by_name("door_ajar")
    occluders = walls_and_door(scene)
    lamp_points = points_on(shape_triangles(scene, "lamp"), POINTS, rng)
    room_points = camera_room_points(POINTS, rng)
    starts, ends = np.repeat(lamp_points, POINTS, axis=0), np.tile(room_points, (POINTS, 1))
    assert blocked(starts, ends, occluders).all(), "a straight line joins the lamp to the camera's room"


def test_door_ajar_gap_lets_the_lit_room_see_into_the_camera_room():
    rng = np.random.default_rng(SEED)
    scene = scene_by_name("door_ajar")
    occluders = walls_and_door(scene)
    # points on the lit room's far wall, just in front of it, against points in the camera's room
    wall_points = points_on(shape_triangles(scene, "wall_back"), POINTS, rng) - np.array([0.0, 0.0, 1e-3])
    room_points = camera_room_points(POINTS, rng)
    starts, ends = np.repeat(wall_points, POINTS, axis=0), np.tile(room_points, (POINTS, 1))
    seen = ~blocked(starts, ends, occluders)
    # through a gap of a few per cent of the wall: some segments pass, most do not
    assert 0 < seen.mean() < 0.2, f"{seen.mean():.3f} of the segments pass the door"


def test_caustic_pixels_see_the_floor_in_front_of_the_sphere():
    scene = scene_by_name("caustic")
    mask = caustic_mask(scene.camera, SIZE, SIZE)
    assert 0.01 < mask.mean() < 0.3
    centre = caustic_centre()
    # the caustic's centre lies on the floor, between the sphere's foot and the camera
    assert centre[1] == 0.0 and scene.camera.position[2] < centre[2] < SPHERE_CENTRE[2]
    # the masked pixels lie below the image's middle row: the floor in front of the sphere
    rows = np.nonzero(mask)[0]
    assert rows.min() > SIZE // 2


def test_glossy_through_glossy_lamp_is_outside_the_picture():
    scene = scene_by_name("glossy_through_glossy")
    right, up, forward = scene.camera.image_plane(SIZE, SIZE)
    lamp = shape_triangles(scene, "lamp")
    offsets = lamp.reshape(-1, 3) - np.asarray(scene.camera.position)
    depth = offsets @ forward
    vertical = offsets @ up / np.dot(up, up) / depth
    # image y = offset . up / |up|^2 / depth spans [-1, 1] on screen: the lamp is above it
    assert np.all(depth > 0) and np.all(vertical > 1.0)
