"""`wgputrace render --tonemap ... --exposure EV|auto`: the PNG holds `tonemap`'s picture of the
linear image, auto-exposure measured on that image, and its metadata says how it was made."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from wgputrace import load_image
from wgputrace.image_io import auto_exposure, srgb8, tonemap
from wgputrace.provenance import NAMESPACE, read_metadata

pytestmark = pytest.mark.gpu  # every command here opens the adapter

RENDER = ("render", "sunlit_spheres", "--spp", "2", "--size", "24x16", "--seed", "4")


@pytest.mark.parametrize(("operator", "exposure"), [("agx", "auto"), ("aces", "-1.5"), ("pbr_neutral", "0.75")])
def test_a_png_is_the_tone_mapped_linear_image(tmp_path, run_cli, operator, exposure):
    linear, png = tmp_path / "linear.npy", tmp_path / "picture.png"
    assert run_cli(*RENDER, "-o", str(linear)).returncode == 0
    result = run_cli(*RENDER, "--tonemap", operator, "--exposure", exposure, "-o", str(png))
    assert result.returncode == 0, result.stderr
    image = load_image(linear)
    stops = auto_exposure(image) if exposure == "auto" else float(exposure)
    np.testing.assert_array_equal(np.asarray(Image.open(png).convert("RGB")), srgb8(tonemap(image, operator, stops)))
    metadata = read_metadata(png)
    assert metadata[NAMESPACE + "tonemap"] == operator
    shown = f"{stops:+.3g} EV"
    assert metadata[NAMESPACE + "exposure"] == (f"auto: {shown}" if exposure == "auto" else shown)
    assert metadata[NAMESPACE + "camera"].startswith("Camera: position ")
    # a linear file has no tone mapping to record
    assert NAMESPACE + "tonemap" not in read_metadata(linear)


@pytest.mark.parametrize(
    ("option", "value", "message"),
    [
        ("--tonemap", "filmic", "argument --tonemap: invalid choice: 'filmic'"),
        ("--exposure", "bright", "argument --exposure: must be a finite number of stops (EV) or auto, got 'bright'"),
        ("--exposure", "nan", "got 'nan'"),
    ],
)
def test_bad_tone_options_are_one_line(tmp_path, run_cli, option, value, message):
    result = run_cli("render", option, value, "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2 and message in result.stderr and len(result.stderr.splitlines()) == 1
