"""The test scenes render from the command line by name, as a user would run them."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import load_image

pytestmark = pytest.mark.gpu


def test_render_a_test_scene_by_name(tmp_path, run_cli):
    out = tmp_path / "tiny_light.npy"
    result = run_cli("render", "tiny_light", "--spp", "1", "--size", "8x8", "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert "tiny_light: 676 triangles" in result.stdout
    image = load_image(out)
    assert image.shape == (8, 8, 3) and np.isfinite(image).all()
