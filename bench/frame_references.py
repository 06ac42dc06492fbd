"""Converged references of every frame of a fly-through, rendered once and cached on disk.

Each frame's reference is two independent halves (seeds of their own, never a mode's, and never
another frame's, so that frame-to-frame differences of references carry independent noise); the
cache keeps them as displayed (`frame_metrics.displayed`): each half and their mean's picture, 8-bit.
A cached file is named for the fly-through, its pose's digest (`FlyThrough.key`), the size, the
samples, the depth and the display tone, so that a changed pose or setting renders anew.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.command_line import log
from bench.fly_throughs import FlyThrough
from bench.frame_metrics import DISPLAY_TONE, displayed, reference_noise
from bench.validation import image_failures
from wgputrace import Renderer

# The references' seeds start here, two per frame: far from any mode's seed.
REFERENCE_SEED = 1_000_000
# The reference's samples are added in renders of at most this many, so that no dispatch runs long.
REFERENCE_CHUNK_SPP = 8


def default_cache() -> Path:
    """$XDG_CACHE_HOME/wgputrace/realtime (~/.cache when unset): outside the checkout."""
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "wgputrace" / "realtime"


@dataclass
class FrameReference:
    """A frame's reference as displayed (float64 in [0, 1]), its noise (`reference_noise`) and its
    halves (each half the samples) as displayed."""

    shown: np.ndarray
    noise: float
    halves: tuple[np.ndarray, np.ndarray]


class FrameReferences:
    """The references of `fly`'s frames at `width` x `height`, `spp` samples in all (half each
    half), from `cache` or rendered (one Renderer, its scene posed frame by frame)."""

    def __init__(self, fly: FlyThrough, width: int, height: int, spp: int, max_depth: int, cache: Path) -> None:
        if spp < 2 or spp % 2:
            raise ValueError(f"a reference takes an even number of samples (two halves), at least 2; got {spp}")
        self.fly, self.width, self.height, self.spp, self.max_depth = fly, width, height, spp, max_depth
        self.cache = cache
        self.rendered = 0  # frames rendered rather than read from the cache
        self._scene = fly.build()
        self._renderer: Renderer | None = None

    def path(self, frame: int) -> Path:
        tone = f"{DISPLAY_TONE.operator}{DISPLAY_TONE.ev:g}"
        name = (
            f"{self.fly.name}_{self.fly.key(frame)}_{self.width}x{self.height}_{self.spp}spp_d{self.max_depth}_{tone}"
        )
        return self.cache / f"{name}.npz"

    def __getitem__(self, frame: int) -> FrameReference:
        path = self.path(frame)
        if not path.is_file():
            self._render(frame, path)
        with np.load(path) as stored:
            halves = [stored[name] / 255.0 for name in ("half_a", "half_b")]
            return FrameReference(stored["full"] / 255.0, reference_noise(*halves), (halves[0], halves[1]))

    def _half(self, seed: int) -> np.ndarray:
        renderer = self._renderer
        renderer.restart(seed=seed)
        for _ in range(0, self.spp // 2, REFERENCE_CHUNK_SPP):
            renderer.render(min(REFERENCE_CHUNK_SPP, self.spp // 2 - renderer.samples_per_pixel))
        image = renderer.image()
        failures = image_failures(image, renderer.dropped_samples)
        if failures:
            raise SystemExit(f"{self.fly.name}'s reference (seed {seed}): {'; '.join(failures)}")
        return image

    def _render(self, frame: int, path: Path) -> None:
        self.fly.pose(self._scene, frame)
        if self._renderer is None:
            self._renderer = Renderer(self._scene, self.width, self.height, max_depth=self.max_depth)
        self._renderer.update()
        half_a, half_b = (self._half(REFERENCE_SEED + 2 * frame + k) for k in range(2))
        path.parent.mkdir(parents=True, exist_ok=True)
        shown = {"half_a": displayed(half_a), "half_b": displayed(half_b), "full": displayed((half_a + half_b) / 2)}
        np.savez_compressed(path, **{name: np.round(value * 255.0).astype(np.uint8) for name, value in shown.items()})
        self.rendered += 1
        log(f"  reference {self.fly.name} frame {frame}: {self.spp} spp, written to {path.name}")
