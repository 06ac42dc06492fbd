"""Cutting a render into batches of samples over the whole image, and each batch's seed.

A batch is (index, seed, spp). Its seed comes from the render's seed and the batch's index alone,
and the batch count from the caller or the samples alone, never from the workers: so the batches,
and each batch's image, are the same however many workers there are and wherever each runs. Batch 0
keeps the render's own seed, so a render in one batch is `wgputrace.render`'s image bit for bit;
the others' seeds go through numpy's SeedSequence (a hash of seed and index), so no two batches
start their pixels' random streams close together.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Batches when the caller does not say (fewer where there are fewer samples per pixel). Each batch
# costs the same fixed time (read-back, the call, the driver's fetch and merge), so a fixed count
# keeps the job's overhead a share that shrinks as its samples grow (bench/README.md, "Rendering on
# a cluster"). It also caps the workers a job can use: a larger cluster wants more batches
# (batches=, --batches).
DEFAULT_BATCHES = 64
_SEED_BITS = 0xFFFF_FFFF_FFFF_FFFF


@dataclass(frozen=True)
class Batch:
    """`spp` samples per pixel of the whole image, from the random streams of `seed`."""

    index: int
    seed: int
    spp: int


def batch_seed(seed: int, index: int) -> int:
    """The seed of batch `index` of a render seeded with `seed`: `seed` itself for batch 0."""
    if index == 0:
        return seed
    state = np.random.SeedSequence([seed & _SEED_BITS, index]).generate_state(1, np.uint64)
    return int(state[0])


def split_samples(spp: int, seed: int, batches: int | None = None) -> list[Batch]:
    """`spp` samples per pixel in `batches` batches (None: DEFAULT_BATCHES, or one per sample where
    there are fewer) whose sizes differ by at most one, the larger first."""
    if spp < 1:
        raise ValueError(f"spp must be at least 1, got {spp}")
    count = min(DEFAULT_BATCHES, spp) if batches is None else batches
    if not 1 <= count <= spp:
        raise ValueError(f"batches must be from 1 to spp ({spp}), got {count}")
    size, larger = divmod(spp, count)
    return [Batch(index, batch_seed(seed, index), size + (index < larger)) for index in range(count)]
