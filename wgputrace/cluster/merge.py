"""Merging batch images into one mean, the same bits whatever order they arrive in.

A worker sends a batch's mean as float32 with its sample count; mean x count is exact in float64
(a float32 significand times a count below 2^29 fits in 53 bits), so the driver recovers the
batch's sum without the worker sending float64 sums at twice the bytes. The sums are added in
batch order, in float64: a batch that arrives early waits for those before it, so the total, and
the image, do not depend on which worker finished first.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .tiles import Tile


@dataclass(frozen=True)
class BatchImage:
    """A batch's result: the mean of its `samples` samples per pixel (float32 (H, W, 3)) and how
    many of them the renderer dropped (non-finite or cut short; counted as zero in the mean)."""

    index: int
    mean: np.ndarray
    samples: int
    dropped: int = 0


@dataclass
class OrderedSum:
    """The float64 sum of batch images added in batch order (0, 1, 2, ...), whatever order `add`
    receives them in."""

    total: np.ndarray | None = None  # allocated by the first batch, in its shape
    samples: int = 0
    dropped: int = 0
    next_index: int = 0
    waiting: dict[int, BatchImage] = field(default_factory=dict)

    def add(self, batch: BatchImage) -> None:
        if batch.index < self.next_index or batch.index in self.waiting:
            raise ValueError(f"batch {batch.index} was merged already")
        if self.total is None:
            self.total = np.zeros(batch.mean.shape, np.float64)
        if batch.mean.shape != self.total.shape:
            raise ValueError(f"batch {batch.index} has shape {batch.mean.shape}, expected {self.total.shape}")
        self.waiting[batch.index] = batch
        while self.next_index in self.waiting:
            ready = self.waiting.pop(self.next_index)
            self.total += ready.mean.astype(np.float64) * ready.samples
            self.samples += ready.samples
            self.dropped += ready.dropped
            self.next_index += 1

    def image(self) -> np.ndarray:
        """The mean over every batch merged so far, float32 (H, W, 3); batches still waiting for an
        earlier one are not in it."""
        if self.total is None:
            raise ValueError("no batch merged yet")
        return (self.total / max(self.samples, 1)).astype(np.float32)


@dataclass
class TiledSum:
    """An OrderedSum per tile of a `width` x `height` image, and the image they make together."""

    width: int
    height: int
    tiles: list[Tile]
    sums: dict[int, OrderedSum] = field(init=False)

    def __post_init__(self) -> None:
        self.sums = {tile.index: OrderedSum() for tile in self.tiles}

    def add(self, tile: Tile, batch: BatchImage) -> None:
        self.sums[tile.index].add(batch)

    @property
    def dropped(self) -> int:
        return sum(merged.dropped for merged in self.sums.values())

    def image(self) -> np.ndarray:
        """float32 (height, width, 3): every tile's mean in its place."""
        image = np.empty((self.height, self.width, 3), np.float32)
        for tile in self.tiles:
            image[tile.y : tile.y + tile.height, tile.x : tile.x + tile.width] = self.sums[tile.index].image()
        return image
