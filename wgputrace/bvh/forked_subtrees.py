"""Growing a BVH's subtrees side by side in forked worker processes.

numpy's `ufunc.at` scatters hold the GIL, so threads cannot share a level's work, but independent
subtrees can go to processes. Workers are `os.fork` children (Linux only): they inherit the
level's records without a copy, write into shared memory and leave with `os._exit`, touching
nothing else of the parent's (not its GPU device, not its threads); a failed worker's group is
grown again by the parent. The merged tree is renumbered breadth first, as one process numbers it,
so the tree does not depend on the worker count.
"""

from __future__ import annotations

import mmap
import os
import sys
import warnings
from collections.abc import Callable

import numpy as np

# Smaller builds take a few hundredths of a second, where a fork's cost shows; above it forking
# pays (`python -m bench.bvh_build --triangles 8000 16000 32000 --repeats 7`, bench/README.md's log).
FORK_MIN_TRIANGLES = 1 << 14
# A level is cut into groups once the largest group holds at most this multiple of a fair share.
MAX_GROUP_IMBALANCE = 1.2


def available_workers() -> int:
    """Worker processes a build may use: the CPUs this process may run on, where fork exists."""
    if not sys.platform.startswith("linux"):
        return 1
    return len(os.sched_getaffinity(0))


def shared_empty(shape: tuple[int, ...], dtype: np.dtype) -> np.ndarray:
    """An uninitialized array in anonymous shared memory, written by forked workers and read by
    their parent (pages are committed only when touched)."""
    size = int(np.prod(shape)) * np.dtype(dtype).itemsize
    return np.frombuffer(mmap.mmap(-1, max(size, 1)), dtype, int(np.prod(shape))).reshape(shape)


def balanced_groups(count: np.ndarray, workers: int) -> np.ndarray | None:
    """Edges (node indices, first 0, last count.size) cutting a level's consecutive nodes of
    `count` triangles into `workers` groups of about equal triangle totals, or None where no cut
    is within MAX_GROUP_IMBALANCE of a fair share (a large node would make one group too big)."""
    if count.size < workers:
        return None
    cumulative = np.cumsum(count)
    share = cumulative[-1] / workers
    # a cut after node i leaves cumulative[i] triangles before it; take the nearest to each target
    targets = share * np.arange(1, workers)
    after = np.searchsorted(cumulative, targets)
    below = np.maximum(after - 1, 0)
    nearest = np.where(np.abs(cumulative[below] - targets) < np.abs(cumulative[after] - targets), below, after)
    edges = np.concatenate([[0], nearest + 1, [count.size]])
    totals = np.diff(np.concatenate([[0], cumulative])[edges])
    if np.any(np.diff(edges) <= 0) or totals.max() > MAX_GROUP_IMBALANCE * share:
        return None
    return edges


def grow_groups(group_count: int, grow: Callable[[int], int]) -> list[int]:
    """Run `grow(group)` for every group, group 0 in this process and the others in forked
    workers; each returns the depth its subtrees reached. Returns the depths in group order."""
    depths = shared_empty((group_count,), np.int64)
    children = {}
    for group in range(1, group_count):
        with warnings.catch_warnings():
            # Python 3.12+ warns that forking a multi-threaded process may deadlock a child that
            # takes a lock another thread held. The worker takes none: it runs numpy on memory
            # it owns or shares, then leaves with os._exit.
            warnings.simplefilter("ignore", DeprecationWarning)
            pid = os.fork()
        if pid == 0:
            status = 1
            try:
                depths[group] = grow(group)
                status = 0
            finally:
                os._exit(status)
        children[group] = pid
    depths[0] = grow(0)
    for group, pid in children.items():
        _, status = os.waitpid(pid, 0)
        if status != 0:  # killed or failed: its group is grown again here, over what it left
            depths[group] = grow(group)
    return [int(depth) for depth in depths]
