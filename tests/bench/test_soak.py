"""bench.soak: its trend measure, its console lines as recorded, and its place outside the default benchmark run."""

from __future__ import annotations

import numpy as np
import pytest

from bench.__main__ import BENCHMARKS
from bench.soak import FLAT_GROWTH_MIB, WARMUP_FRACTION, memory_trend, recorded_lines


def test_a_steady_leak_is_measured_and_not_flat():
    x = np.linspace(0.0, 100.0, 101)
    kib = 500_000 + 1024 * x  # 1 MiB per unit
    trend = memory_trend(list(x), list(kib.astype(int)))
    assert trend["slope_kib_per_unit"] == pytest.approx(1024, rel=1e-6)
    assert trend["fitted_growth_mib"] == pytest.approx(100 * (1 - WARMUP_FRACTION), rel=1e-6)
    assert not trend["flat"]


def test_warm_up_growth_alone_is_flat():
    x = np.arange(100.0)
    kib = np.where(x < 100 * WARMUP_FRACTION, 400_000 + 10_000 * x, 600_000)  # grows, then stays
    trend = memory_trend(list(x), list(kib.astype(int)))
    assert trend["flat"] and abs(trend["fitted_growth_mib"]) < FLAT_GROWTH_MIB


def test_soak_runs_only_when_named():
    soak = next(benchmark for benchmark in BENCHMARKS if benchmark.name == "soak")
    assert not soak.in_default_run


def test_console_lines_are_recorded_without_the_scene_folder(tmp_path):
    lines = [f"wgputrace view: {tmp_path / 'soak_scene.py'} changed, reloading"]
    assert recorded_lines(lines, tmp_path) == ["wgputrace view: WORKDIR/soak_scene.py changed, reloading"]
