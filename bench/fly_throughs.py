"""The fly-throughs `bench.realtime` renders: a scene and where its camera and moving shapes are at
each frame, through the public API only (`Scene.camera`, `Shape.transform`).

Frame k of every fly-through is the same pose however many frames a run takes: the path advances by
1 / FULL_FRAMES of its length per frame, so a shorter run (`--frames`) is the start of the full
one, moves as fast, and shares its cached references.

- `cornell`: the camera swings and dollies through the Cornell box's open side.
- `asset`: the built-in `textured_asset` (a generated panel carrying base colour, metallic-roughness,
  normal and emission textures, on a floor) under the generated sunny sky of `environment_lit`,
  its point light removed; the camera orbits the panel.
- `moving`: the Cornell box from its own camera, the glass sphere sliding from side to side and the
  diffuse box turning about its vertical axis.

`STREET` (`bench.restir --fly`, not `bench.realtime`'s): a walk down the built-in `night_street`
under its 1,065 windows and 24 lamps, looking ahead and a little up, swaying from kerb to kerb.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from wgputrace.scene import Camera, Scene, Shape
from wgputrace.scene.lights.environment import Environment
from wgputrace.scenes import scene_by_name
from wgputrace.scenes.environment_lit import sunny_sky

# The full fly-through: six seconds at the viewer's 20 frames per second.
FULL_FRAMES = 120
# Cornell box: the camera swings by this many radians either side about the box's centre line...
CORNELL_SWING_RADIANS = 0.2
# ... at a distance from the box's centre falling from the first to the second, and looks here.
CORNELL_DISTANCE = (1.65, 1.3)
CORNELL_TARGET = (0.0, 0.35, 0.0)
CORNELL_HEIGHT = 0.35
# The asset: the camera orbits the panel's centre by this many radians either side, at this
# distance and height.
ASSET_ORBIT_RADIANS = 0.6
ASSET_DISTANCE = 3.2
ASSET_HEIGHT = 0.35
ASSET_TARGET = (0.0, 0.1, 0.0)
# The sky's sun is 1,500 times brighter than the sky; this scale keeps the lit panel within the
# display's range at exposure 0, as the viewer shows it.
ASSET_SKY_INTENSITY = 0.5
# Moving objects: the glass sphere slides this far either side of where it stands, once per
# MOVING_PERIOD of the path; the diffuse box turns once per path.
SPHERE_SLIDE = 0.25
MOVING_PERIOD = 0.5
SPHERE = "sphere1"
BOX = "box1"
# The street: the camera walks from the first z to the second at eye height, swaying this far
# either side of the street's middle twice along the path, and looks this far ahead and this high.
STREET_WALK = (-7.0, 5.0)
STREET_EYE_HEIGHT = 1.7
STREET_SWAY = 1.2
STREET_LOOK_AHEAD = 12.0
STREET_LOOK_HEIGHT = 4.0


@dataclass(frozen=True)
class FlyThrough:
    """A scene (`build` makes a fresh one) and `pose(scene, frame)`, which puts its camera and
    moving shapes where they are at `frame`; `moves_shapes`: whether any shape's transform changes."""

    name: str
    description: str
    build: Callable[[], Scene]
    pose: Callable[[Scene, int], None]
    moves_shapes: bool = False

    def key(self, frame: int) -> str:
        """A digest of what frame `frame` shows (camera and every shape's transform): a cached
        reference is of this pose."""
        scene = self.build()
        self.pose(scene, frame)
        digest = hashlib.sha256(repr(scene.camera).encode())
        for shape in scene.shapes:
            digest.update(np.ascontiguousarray(shape.transform, np.float64).tobytes())
        return digest.hexdigest()[:16]


def path_position(frame: int) -> float:
    """Where frame `frame` is along the path: 0 at the first frame, 1 at FULL_FRAMES."""
    return frame / FULL_FRAMES


def pose_cornell(scene: Scene, frame: int) -> None:
    s = path_position(frame)
    angle = CORNELL_SWING_RADIANS * math.sin(2.0 * math.pi * s)
    distance = CORNELL_DISTANCE[0] + (CORNELL_DISTANCE[1] - CORNELL_DISTANCE[0]) * s
    x, _, z = CORNELL_TARGET
    position = (x + distance * math.sin(angle), CORNELL_HEIGHT, z - distance * math.cos(angle))
    scene.camera = Camera.looking_at(position, CORNELL_TARGET, vfov_degrees=scene.camera.vfov_degrees)


def asset_scene() -> Scene:
    scene = scene_by_name("textured_asset")
    scene.remove_light(*scene.lights)
    scene.environment = Environment(texels=sunny_sky(), intensity=ASSET_SKY_INTENSITY, source="sunny_sky")
    return scene


def pose_asset(scene: Scene, frame: int) -> None:
    angle = ASSET_ORBIT_RADIANS * math.sin(2.0 * math.pi * path_position(frame))
    x, _, z = ASSET_TARGET
    position = (x + ASSET_DISTANCE * math.sin(angle), ASSET_HEIGHT, z + ASSET_DISTANCE * math.cos(angle))
    scene.camera = Camera.looking_at(position, ASSET_TARGET, vfov_degrees=scene.camera.vfov_degrees)


def about_centre(shape: Shape, rotation: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """4x4: turn by the 3x3 `rotation` about the centre of the shape's own vertices (before its
    transform), then move by `offset`."""
    centre = shape.vertices.reshape(-1, 3).astype(np.float64).mean(axis=0)
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = centre - rotation @ centre + offset
    return matrix


def pose_moving(scene: Scene, frame: int) -> None:
    s = path_position(frame)
    shapes = {shape.name: shape for shape in scene.shapes}
    slide = SPHERE_SLIDE * math.sin(2.0 * math.pi * s / MOVING_PERIOD)
    sphere = shapes[SPHERE]
    sphere.transform = about_centre(sphere, np.eye(3), np.array([slide, 0.0, 0.0]))
    turn = 2.0 * math.pi * s
    cos, sin = math.cos(turn), math.sin(turn)
    box = shapes[BOX]
    rotation = np.array([[cos, 0.0, sin], [0.0, 1.0, 0.0], [-sin, 0.0, cos]])
    box.transform = about_centre(box, rotation, np.zeros(3))


def pose_street(scene: Scene, frame: int) -> None:
    s = path_position(frame)
    z = STREET_WALK[0] + (STREET_WALK[1] - STREET_WALK[0]) * s
    x = STREET_SWAY * math.sin(4.0 * math.pi * s)
    position = (x, STREET_EYE_HEIGHT, z)
    scene.camera = Camera.looking_at(
        position, (0.5 * x, STREET_LOOK_HEIGHT, z + STREET_LOOK_AHEAD), vfov_degrees=scene.camera.vfov_degrees
    )


STREET = FlyThrough(
    "street",
    "a walk down night_street (1,065 windows, 24 lamps), swaying from kerb to kerb",
    lambda: scene_by_name("night_street"),
    pose_street,
)

FLY_THROUGHS = {
    fly.name: fly
    for fly in (
        FlyThrough(
            "cornell",
            "the camera swings and dollies through the Cornell box",
            lambda: scene_by_name("cornell"),
            pose_cornell,
        ),
        FlyThrough(
            "asset",
            "the camera orbits textured_asset (generated base colour, metallic-roughness, normal and emission "
            "textures) under the generated sunny sky, its point light removed",
            asset_scene,
            pose_asset,
        ),
        FlyThrough(
            "moving",
            "the Cornell box from its own camera, the glass sphere sliding and the diffuse box turning (Shape.transform)",
            lambda: scene_by_name("cornell"),
            pose_moving,
            moves_shapes=True,
        ),
    )
}
