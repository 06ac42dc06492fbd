"""`wgputrace render --denoise`, in process through wgputrace.cli.main: the denoised Cornell box at 4
spp is much nearer the Mitsuba reference than the raw image, an .exr keeps the raw image and the
guides as layers and the metadata names the denoiser and its device; an interrupted render writes
the denoised image of the samples done; without the denoise extra it says how to install it,
before rendering anything."""

from __future__ import annotations

import importlib
import signal
import sys

import numpy as np
import pytest

from wgputrace import Renderer, load_image
from wgputrace.cli import main
from wgputrace.image_io import load_layers
from wgputrace.provenance import NAMESPACE, read_metadata
from wgputrace.testing.image_statistics import displayed_mse
from wgputrace.testing.references import load_reference

# wgputrace.denoise is the function the package exports; the module holds the device and its cache.
denoise_module = importlib.import_module("wgputrace.denoise")

SCENE, SPP, SEED = "cornell", 4, 2
LAYERS = ["raw", "albedo", "normal"]
# Displayed (sRGB, clipped) MSE against the reference, denoised over raw, at 128x128 and 4 spp:
# measured 0.055 to 0.065 over seeds 1-8 (colour alone 0.061 to 0.069).
ERROR_LEFT_BOUND = 0.15
INTERRUPTED_SIZE = 32


def denoised_from_layers(path) -> tuple[np.ndarray, np.ndarray]:
    """The file's main image, and the raw image in its layers denoised with its guides."""
    layers = load_layers(path)
    assert sorted(layers) == sorted(LAYERS)
    return load_image(path), denoise_module.denoise(layers["raw"], layers["albedo"], layers["normal"])


@pytest.mark.gpu
def test_denoise_writes_the_denoised_image_nearer_the_reference(tmp_path, capsys):
    pytest.importorskip("pyoidn", reason="the denoise extra (pyoidn) is not installed")
    reference = load_reference(SCENE)
    height, width, _ = reference.estimate.mean.shape
    output = tmp_path / "denoised.exr"
    command = ["render", SCENE, "--spp", str(SPP), "--size", f"{width}x{height}", "--seed", str(SEED)]
    assert main([*command, "--max-depth", str(reference.metadata["max_depth"]), "--denoise", "-o", str(output)]) == 0
    image, expected = denoised_from_layers(output)
    assert image.shape == (height, width, 3) and np.all(np.isfinite(image))
    np.testing.assert_array_equal(image, expected)
    raw_error = displayed_mse(load_layers(output)["raw"], reference.estimate.mean)
    assert displayed_mse(image, reference.estimate.mean) < ERROR_LEFT_BOUND * raw_error
    device = denoise_module.denoiser_device()
    metadata = read_metadata(output)
    assert metadata[NAMESPACE + "denoised"] == "oidn" and metadata[NAMESPACE + "denoiser_device"] == device
    assert f"Intel Open Image Denoise on {device}" in capsys.readouterr().out


@pytest.mark.gpu
def test_an_interrupted_denoise_render_writes_the_denoised_samples_done(tmp_path, monkeypatch):
    """A SIGINT raised right after the first sample per pixel: the render stops there (exit 130)
    and the file holds that sample denoised."""
    pytest.importorskip("pyoidn", reason="the denoise extra (pyoidn) is not installed")
    render = Renderer.render

    def render_interrupted_after_one_batch(self, spp=None, progress=None, **options):
        def progress_then_interrupt(samples: int) -> None:
            progress(samples)
            signal.raise_signal(signal.SIGINT)

        return render(self, spp, progress_then_interrupt, **options)

    monkeypatch.setattr(Renderer, "render", render_interrupted_after_one_batch)
    output = tmp_path / "stopped.exr"
    size = f"{INTERRUPTED_SIZE}x{INTERRUPTED_SIZE}"
    assert main(["render", "--spp", "1000", "--size", size, "--denoise", "-o", str(output)]) == 130
    metadata = read_metadata(output)
    assert metadata[NAMESPACE + "spp"] == "1" and metadata[NAMESPACE + "stopped_by"] == "SIGINT"
    assert metadata[NAMESPACE + "denoised"] == "oidn"
    image, expected = denoised_from_layers(output)
    np.testing.assert_array_equal(image, expected)


def test_without_the_extra_it_says_how_to_install_it_before_rendering(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "pyoidn", None)  # import pyoidn raises ImportError
    monkeypatch.setattr(denoise_module, "_shared", None)  # no device made before the import failed
    output = tmp_path / "never.png"
    assert main(["render", "--spp", "1", "--size", "8x8", "--denoise", "-o", str(output)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1
    assert err.startswith("wgputrace: error: --denoise: ")
    assert 'pip install "wgputrace[denoise]"' in err and "wgputrace view --filter" in err
    assert "rendering" not in err and not output.exists()
