"""Host memory stays flat while the path tracer runs: Mesa 22.3's lavapipe kept about 1.1 MiB per
dispatch of a kernel that read a uniform buffer (why `bindings.UNIFORM` parameters are bound as
read-only storage). The soak benchmark (`bench.soak`) watches the same over minutes."""

from __future__ import annotations

import sys

import pytest

import wgputrace as wt

pytestmark = pytest.mark.gpu

DISPATCHES = 150
# What the leak would have added over DISPATCHES, about 160 MiB, is far above this; the allocator's
# own settling after the warm-up stays far below it.
FLAT_MIB = 24.0


def resident_mib() -> float:
    with open("/proc/self/status") as status:
        line = next(line for line in status if line.startswith("VmRSS:"))
    return int(line.split()[1]) / 1024


@pytest.mark.skipif(sys.platform != "linux", reason="reads /proc/self/status")
def test_rendering_does_not_grow_host_memory():
    renderer = wt.Renderer(wt.default_scene(), 8, 8, seed=3)
    renderer.render(8)  # compile, caches, the allocator's first pools
    before = resident_mib()
    for _ in range(DISPATCHES):
        renderer.render(1)
    grown = resident_mib() - before
    assert grown < FLAT_MIB, f"host memory grew {grown:.1f} MiB over {DISPATCHES} dispatches"
