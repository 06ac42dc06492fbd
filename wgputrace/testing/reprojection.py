"""A scene whose temporal tests have closed forms: a wall facing a pinhole camera with a card in
front of it, both axis-aligned, so what each pixel's centre ray hits and where another camera saw
that point are known without tracing (`centre_hits`, `raster_of`), and which history taps pass
(`reprojection_taps`). The card may move within its plane (`card_move`), as a shape or an
instance (`card_scene(instanced=True)`, `card_object`)."""

from __future__ import annotations

import numpy as np

from ..render.temporal_accumulation import BILINEAR_WEIGHT_MIN
from ..scene import Camera, Diffuse, Material, Scene, Shape, ThinLensCamera
from ..scene.instances import Instance
from ..scene.lights.environment import Environment

# The image is SIZE x SIZE pixels under a 90-degree field of view: seen from pinhole(0) at
# distance z the image spans x and y in [-z, z].
SIZE = 32
WALL_DISTANCE = 4.0
CARD_DISTANCE = 2.0
# The card's raster columns and rows seen from pinhole(0): whole pixels, so no pixel centre lies
# near its edges. The camera looks along +z with +y up, so the world's +x is on the image's left.
CARD_COLUMNS = (10, 20)
CARD_ROWS = (8, 24)
_WALL_HALF_SIZE = 40.0


def pinhole(x: float, yaw_degrees: float = 0.0, aperture_radius: float = 0.0) -> Camera:
    """The camera at (x, 0, 0) looking along +z turned by `yaw_degrees` about +y, 90 degrees
    from the image's bottom to its top; with `aperture_radius`, a thin lens of that radius
    focused on the wall, whose rays through the lens's centre are the pinhole's."""
    yaw = np.radians(yaw_degrees)
    view = {"position": (x, 0.0, 0.0), "forward": (np.sin(yaw), 0.0, np.cos(yaw)), "up": (0.0, 1.0, 0.0)}
    if aperture_radius:
        return ThinLensCamera(**view, vfov_degrees=90.0, aperture_radius=aperture_radius, focus_distance=WALL_DISTANCE)
    return Camera(**view, vfov_degrees=90.0)


def _plane(raster: float) -> float:
    """-x (or -y) at distance 1 from pinhole(0) of a raster column (or row)."""
    return raster / (SIZE / 2) - 1.0


_CARD_X = (-_plane(CARD_COLUMNS[1]) * CARD_DISTANCE, -_plane(CARD_COLUMNS[0]) * CARD_DISTANCE)
_CARD_Y = (-_plane(CARD_ROWS[1]) * CARD_DISTANCE, -_plane(CARD_ROWS[0]) * CARD_DISTANCE)


def _quad(name: str, x: tuple[float, float], y: tuple[float, float], z: float, material: Material) -> Shape:
    (x0, x1), (y0, y1) = x, y
    corners = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], np.float32)
    return Shape(name, corners[[[0, 2, 1], [0, 3, 2]]], material)


WHITE = (0.8, 0.8, 0.8)


def wall_scene(wall: Material | None = None, sky: float = 0.5) -> Scene:
    """The wall at WALL_DISTANCE alone, white (WHITE) unless given, seen from pinhole(0) under a
    grey sky of radiance `sky` (0: none): a white wall's radiance is WHITE times `sky` everywhere."""
    wall = wall or Diffuse("white", color=WHITE)
    half = (-_WALL_HALF_SIZE, _WALL_HALF_SIZE)
    return Scene(
        [_quad("wall", half, half, WALL_DISTANCE, wall)], pinhole(0.0), environment=Environment(sky) if sky else None
    )


def card_scene(
    wall: Material | None = None, card: Material | None = None, sky: float = 0.5, instanced: bool = False
) -> Scene:
    """wall_scene with the card at CARD_DISTANCE covering CARD_COLUMNS x CARD_ROWS seen from
    pinhole(0), of the wall's material unless given; `instanced`: the card is an instance of a
    mesh (placed by the identity) rather than a shape."""
    scene = wall_scene(wall, sky)
    quad = _quad("card", _CARD_X, _CARD_Y, CARD_DISTANCE, card or scene.shapes[0].material)
    if instanced:
        scene.add_instance(quad, np.eye(4), name="card")
    else:
        scene.add(quad)
    return scene


def card_object(scene: Scene) -> Shape | Instance:
    """The card of a card_scene: what its `transform` moves."""
    return scene.instances[0] if scene.instances else scene.shapes[1]


# one pixel's width on the card's plane, seen from pinhole(0)
CARD_PIXEL = 2.0 * CARD_DISTANCE / SIZE


def card_move(offset_pixels: tuple[float, float] = (0.0, 0.0), turn_degrees: float = 0.0) -> np.ndarray:
    """A card transform that keeps it in its plane: turned by `turn_degrees` about its centre's
    normal (+z), then shifted by `offset_pixels` as pinhole(0) sees them (x right, y down: its
    right is the world's -x)."""
    centre = np.array([np.mean(_CARD_X), np.mean(_CARD_Y), CARD_DISTANCE])
    angle = np.radians(turn_degrees)
    turn = np.eye(4)
    turn[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
    to_centre, back = np.eye(4), np.eye(4)
    to_centre[:3, 3], back[:3, 3] = -centre, centre
    shift = np.eye(4)
    shift[:2, 3] = -offset_pixels[0] * CARD_PIXEL, -offset_pixels[1] * CARD_PIXEL
    return shift @ back @ turn @ to_centre


def pixel_centres(within: tuple[float, float] = (0.5, 0.5)) -> np.ndarray:
    """Raster positions of the pixels' centres (or of the point `within` each pixel, in [0, 1)^2),
    (SIZE, SIZE, 2): x right, y down."""
    rows, columns = np.mgrid[0:SIZE, 0:SIZE].astype(np.float64)
    return np.stack([columns + within[0], rows + within[1]], axis=-1)


def centre_hits(
    camera: Camera, within: tuple[float, float] = (0.5, 0.5), card: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """What each pixel's centre ray (or its ray through `within`, as pixel_centres) from `camera`
    (a pinhole looking towards +z) hits: the points (SIZE, SIZE, 3) and whether each is on the
    card (SIZE, SIZE), else on the wall; `card`: the card's transform (a card_move)."""
    right, up, forward = camera.image_plane(SIZE, SIZE)
    ndc = pixel_centres(within) / (SIZE / 2) - 1.0
    directions = forward + ndc[..., :1] * right - ndc[..., 1:] * up
    origin = np.asarray(camera.position, np.float64)

    def on_plane(z: float) -> np.ndarray:
        return origin + directions * ((z - origin[2]) / directions[..., 2:])

    plane = on_plane(CARD_DISTANCE)
    unmoved = plane if card is None else moved_points(plane, np.linalg.inv(card))
    on_card = (
        (_CARD_X[0] <= unmoved[..., 0])
        & (unmoved[..., 0] <= _CARD_X[1])
        & (_CARD_Y[0] <= unmoved[..., 1])
        & (unmoved[..., 1] <= _CARD_Y[1])
    )
    return np.where(on_card[..., None], plane, on_plane(WALL_DISTANCE)), on_card


def moved_points(points: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """`points` (..., 3) through the 4x4 affine `matrix`, in float64."""
    return np.asarray(points, np.float64) @ matrix[:3, :3].T + matrix[:3, 3]


def raster_of(camera: Camera, points: np.ndarray) -> np.ndarray:
    """Where `camera` (a pinhole) puts `points` (..., 3) on a SIZE x SIZE image: raster positions
    (..., 2), x right, y down."""
    right, up, forward = camera.image_plane(SIZE, SIZE)
    to_points = np.asarray(points, np.float64) - np.asarray(camera.position, np.float64)
    along = to_points @ forward
    ndc = np.stack([(to_points @ right) / (along * (right @ right)), -(to_points @ up) / (along * (up @ up))], axis=-1)
    return (ndc * 0.5 + 0.5) * SIZE


def reprojection_taps(previous: Camera, current: Camera) -> np.ndarray:
    """Whether any of each pixel's bilinear taps into the previous frame passes (SIZE, SIZE): a
    tap of weight at least BILINEAR_WEIGHT_MIN inside the image whose pixel saw, from `previous`,
    the same plane (card or wall) as the pixel sees from `current`."""
    points, on_card = centre_hits(current)
    _, previous_on_card = centre_hits(previous)
    # pixel centres at integers, as the kernel takes them
    position = raster_of(previous, points) - 0.5
    corner = np.floor(position).astype(int)
    fraction = position - corner
    passes = np.zeros(on_card.shape, bool)
    for dx in (0, 1):
        for dy in (0, 1):
            weight = (fraction[..., 0] if dx else 1 - fraction[..., 0]) * (
                fraction[..., 1] if dy else 1 - fraction[..., 1]
            )
            x, y = corner[..., 0] + dx, corner[..., 1] + dy
            inside = (0 <= x) & (x < SIZE) & (0 <= y) & (y < SIZE)
            same = np.zeros_like(inside)
            same[inside] = previous_on_card[y[inside], x[inside]] == on_card[inside]
            passes |= (weight >= BILINEAR_WEIGHT_MIN) & inside & same
    return passes
