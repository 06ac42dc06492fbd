"""Tiles: an image larger than one device allows, rendered as rectangles of it.

A tile is rendered by a Renderer of the tile's size looking through `TileCamera`, the part of the
scene camera's view that the tile covers: its pixels see exactly what the whole image's pixels at
the same place would. Each tile has random streams of its own (its seed derived from the batch's
and the tile's index), so no two tiles repeat one noise pattern. Tiles are fixed by the image and
the tile side alone, never by the workers, so a tiled image is the same bits for any worker count.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene import Camera
from .batches import batch_seed


@dataclass(frozen=True)
class Tile:
    """The rectangle of `width` x `height` pixels at column `x`, row `y` (row 0 on top)."""

    index: int
    x: int
    y: int
    width: int
    height: int

    @property
    def shape(self) -> tuple[int, int]:
        return self.width, self.height

    def seed(self, batch_seed_value: int) -> int:
        """This tile's seed in a batch seeded with `batch_seed_value` (that seed itself for tile 0,
        so an untiled render is unchanged)."""
        return batch_seed(batch_seed_value, self.index)


def split_image(width: int, height: int, side: int | None) -> list[Tile]:
    """Tiles of at most `side` x `side` covering the image, row by row, as even as the pixels
    allow (so at most four tile shapes); one tile when `side` is None or the image fits it."""
    if side is not None and side < 1:
        raise ValueError(f"tile side must be at least 1, got {side}")
    columns = 1 if side is None else -(-width // side)
    rows = 1 if side is None else -(-height // side)
    xs = np.linspace(0, width, columns + 1).round().astype(int)
    ys = np.linspace(0, height, rows + 1).round().astype(int)
    return [
        Tile(
            row * columns + column,
            int(xs[column]),
            int(ys[row]),
            int(xs[column + 1] - xs[column]),
            int(ys[row + 1] - ys[row]),
        )
        for row in range(rows)
        for column in range(columns)
    ]


def check_tileable(camera: Camera) -> None:
    """ValueError unless `camera` is the pinhole `Camera`, the only kind TileCamera cuts."""
    if type(camera) is not Camera:
        raise ValueError(f"tiles cut the pinhole Camera's view only: a {type(camera).__name__} renders untiled")


@dataclass
class TileCamera(Camera):
    """`Camera` seeing only `tile` of its `image_width` x `image_height` view: the image plane of
    the tile is the whole image's plane cut to the tile, centred where the tile is."""

    image_width: int = 1
    image_height: int = 1
    tile: Tile | None = None

    @classmethod
    def of(cls, camera: Camera, width: int, height: int, tile: Tile) -> TileCamera:
        return cls(camera.position, camera.forward, camera.up, camera.vfov_degrees, width, height, tile)

    def image_plane(self, width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        # `camera_ray`: direction = forward + ndc.x right - ndc.y up, ndc in [-1, 1] over the image;
        # a tile's ndc maps to (2 x + w) / W - 1 + ndc w / W on the whole image, alike for rows
        right, up, forward = Camera.image_plane(self, self.image_width, self.image_height)
        tile = self.tile
        centre_x = (2 * tile.x + tile.width) / self.image_width - 1
        centre_y = (2 * tile.y + tile.height) / self.image_height - 1
        return (
            right * (tile.width / self.image_width),
            up * (tile.height / self.image_height),
            forward + centre_x * right - centre_y * up,
        )
