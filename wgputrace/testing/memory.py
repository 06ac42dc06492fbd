"""The host memory a call allocates at its peak, as tracemalloc sees it (what Python and numpy
hold, not wgpu's staging copies), for tests of the limits' memory model (`host_steps`)."""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable

# A traced peak may exceed the model by Python's own bookkeeping, no more.
TRACEMALLOC_SLACK_BYTES = 64 * 1024


def traced_peak(call: Callable[[], object]) -> int:
    """The most bytes traced while `call()` runs; what was allocated before it is not counted."""
    tracemalloc.start()
    try:
        call()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
