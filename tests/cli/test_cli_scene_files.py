"""`wgputrace render FILE`: scene files on the command line, the GPU memory line, load errors."""

from __future__ import annotations

import numpy as np

from tests.cli.test_cli import run_cli
from tests.conftest import SHARED_SCENES
from wgputrace import load_image


def test_render_a_scene_file(tmp_path):
    out = tmp_path / "obj.npy"
    result = run_cli(
        "render", str(SHARED_SCENES / "cornell_trac0r.obj"), "--spp", "1", "--size", "16x12", "-o", str(out)
    )
    assert result.returncode == 0, result.stderr
    assert load_image(out).shape == (12, 16, 3) and np.all(np.isfinite(load_image(out)))
    assert "676 triangles, 6 materials, loaded in" in result.stdout
    assert "B per triangle (triangles, BVH nodes, materials, lights" in result.stdout


def test_a_broken_scene_file_is_named_with_its_line(tmp_path):
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nf 1 2 3\n")
    result = run_cli("render", str(broken), "--spp", "1", "--size", "8x8", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2
    assert f"wgputrace: error: {broken}:3: face vertex index 3 is out of range: 2 vertices" in result.stderr
