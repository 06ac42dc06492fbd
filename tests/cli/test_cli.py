"""The command line, run as a user would: a separate process, files on disk."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgputrace import load_image

REPO_ROOT = Path(__file__).resolve().parents[2]


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "wgputrace", *args], capture_output=True, text=True, timeout=300, cwd=cwd
    )


@pytest.mark.parametrize("suffix", [".png", ".exr", ".npy"])
def test_render_writes_each_format(tmp_path, suffix):
    out = tmp_path / f"cornell{suffix}"
    result = run_cli("render", "--spp", "2", "--size", "24x16", "--seed", "5", "-o", str(out))
    assert result.returncode == 0, result.stderr
    image = load_image(out)
    assert image.shape == (16, 24, 3)
    assert np.all(np.isfinite(image)) and image.max() > 0
    for label in ("adapter", "676 triangles", "SAH cost", "built in", "M samples/s"):
        assert label in result.stdout


def test_exr_and_npy_hold_the_same_linear_image(tmp_path):
    for suffix in (".exr", ".npy"):
        assert run_cli("render", "--spp", "1", "--size", "8x8", "-o", str(tmp_path / f"a{suffix}")).returncode == 0
    np.testing.assert_array_equal(load_image(tmp_path / "a.exr"), load_image(tmp_path / "a.npy"))


def test_errors_are_clear(tmp_path):
    unknown = run_cli("render", "nowhere", "--spp", "1", "-o", str(tmp_path / "x.png"))
    assert unknown.returncode == 2 and "unknown scene 'nowhere'" in unknown.stderr
    bad_format = run_cli("render", "--spp", "1", "--size", "8x8", "-o", str(tmp_path / "x.jpg"))
    assert bad_format.returncode == 2 and "unknown image format '.jpg'" in bad_format.stderr
    bad_size = run_cli("render", "--size", "big")
    assert bad_size.returncode == 2 and "size must look like 512x512" in bad_size.stderr


def test_info_prints_adapter_and_limits():
    result = run_cli("info")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["adapter"] and info["backend"]
    assert "max-storage-buffer-binding-size" in info["limits"]


def test_bench_runs_the_suite_of_the_checkout_it_is_started_in():
    # --help: the suite's own parser answers, so `wgputrace bench` reached bench/__main__.py
    result = run_cli("bench", "--help", cwd=REPO_ROOT)
    assert result.returncode == 0, result.stderr
    assert "python -m bench" in result.stdout and "--only" in result.stdout
