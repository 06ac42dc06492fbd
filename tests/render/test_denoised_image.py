"""A denoised image and what it takes: Renderer.image(denoised=True) denoises the colour alone
without guides and uses the guides where they are on; the guide sums count in the limits checked
before allocation (`limits.pixel_buffers`); an EXR keeps the raw image and the guides as layers beside
the main RGB (image_io.save_image(layers=), load_layers)."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Renderer, default_scene, load_image, save_image
from wgputrace.denoise import denoise
from wgputrace.gpu.device import DeviceLimitError
from wgputrace.image_io import load_layers
from wgputrace.render import limits
from wgputrace.render.limits import GUIDE_BUFFERS, PIXEL_BUFFERS, check_image_size, host_bytes, host_steps
from wgputrace.testing.memory import TRACEMALLOC_SLACK_BYTES, traced_peak

SIZE, SPP, SEED = 48, 4, 3
LAYERS = ("raw", "albedo", "normal")
# Rows of the images probed against a buffer limit: wide enough that the dispatch never binds first.
PROBE_WIDTH = 2048
MEASURED_SIDE = 256


def rendered(guides: bool) -> Renderer:
    renderer = Renderer(default_scene(), SIZE, SIZE, seed=SEED, guides=guides)
    renderer.render(SPP)
    return renderer


@pytest.mark.gpu
def test_without_guides_the_colour_alone_is_denoised():
    pytest.importorskip("pyoidn", reason="the denoise extra (pyoidn) is not installed")
    renderer = rendered(guides=False)
    image, denoised = renderer.image(), renderer.image(denoised=True)
    assert denoised.shape == image.shape and np.all(np.isfinite(denoised))
    np.testing.assert_array_equal(denoised, denoise(image))
    assert not np.array_equal(denoised, image)


@pytest.mark.gpu
def test_with_guides_they_guide_the_denoiser():
    pytest.importorskip("pyoidn", reason="the denoise extra (pyoidn) is not installed")
    renderer = rendered(guides=True)
    image, denoised = renderer.image(), renderer.image(denoised=True)
    np.testing.assert_array_equal(denoised, denoise(image, **renderer.guides()))
    assert not np.array_equal(denoised, denoise(image))


@pytest.fixture
def no_host_check(monkeypatch):
    """Device limits alone: the host's memory unknown, so unchecked."""
    monkeypatch.setattr(limits, "available_host_memory", lambda: None)


@pytest.mark.gpu
def test_guide_sums_count_against_the_buffer_limits(gpu_context, no_host_check, monkeypatch):
    """Where the guide sums (the largest per-pixel buffer) just fit, one more row is refused with
    guides and still fits without them."""
    limit = "max-storage-buffer-binding-size"
    monkeypatch.setitem(gpu_context.device.limits, "max-compute-workgroups-per-dimension", 2**31)
    monkeypatch.setitem(gpu_context.device.limits, "max-buffer-size", 2**62)
    allowed = gpu_context.device.limits[limit]
    record_bytes = GUIDE_BUFFERS["guide sums"]
    assert record_bytes > max(PIXEL_BUFFERS.values())
    rows = allowed // record_bytes // PROBE_WIDTH
    check_image_size(gpu_context, PROBE_WIDTH, rows, guides=True)
    check_image_size(gpu_context, PROBE_WIDTH, rows + 1)
    with pytest.raises(DeviceLimitError) as error:
        check_image_size(gpu_context, PROBE_WIDTH, rows + 1, guides=True)
    assert f"buffer 'guide sums' needs {limit} = {PROBE_WIDTH * (rows + 1) * record_bytes:,}" in str(error.value)
    assert "the largest square image it can render with guides is" in str(error.value)


@pytest.mark.gpu
def test_a_host_short_of_the_guides_memory_refuses_them_before_allocating(gpu_context, monkeypatch):
    pixels = SIZE * SIZE
    without, with_guides = host_bytes(gpu_context, pixels), host_bytes(gpu_context, pixels, guides=True)
    assert with_guides > without
    monkeypatch.setattr(limits, "available_host_memory", lambda: with_guides - 1)
    with pytest.raises(DeviceLimitError, match="one guides\\(\\) read-back"):
        Renderer(default_scene(), SIZE, SIZE, guides=True)
    renderer = Renderer(default_scene(), SIZE, SIZE)
    with pytest.raises(DeviceLimitError):
        renderer.guides_enabled = True
    assert not renderer.guides_enabled and "guide sums" not in renderer.gpu_image_bytes


@pytest.mark.gpu
def test_guides_read_back_peak_is_within_the_model(gpu_context):
    """tracemalloc sees what Python and numpy hold during guides() (the image held beside it), not
    wgpu's staging memory: the model without the staging copies must still cover the peak."""
    renderer = Renderer(default_scene(), MEASURED_SIDE, MEASURED_SIDE, guides=True)
    image = renderer.image()
    renderer.guides()  # the first read-back of a buffer sets up wgpu-py's state for it
    peak = traced_peak(renderer.guides)
    pixels = image.shape[0] * image.shape[1]
    staging = pixels * (PIXEL_BUFFERS["accumulation"] + GUIDE_BUFFERS["guide sums"])
    # the image, which the model holds beside the guides, was allocated before tracing began
    held_before = image.nbytes
    assert peak <= max(host_steps(pixels, guides=True).values()) - staging - held_before + TRACEMALLOC_SLACK_BYTES


def test_exr_layers_round_trip(tmp_path, rng):
    import OpenEXR

    image = rng.random((5, 7, 3), dtype=np.float32)
    layers = {name: rng.standard_normal((5, 7, 3)).astype(np.float32) for name in LAYERS}
    path = save_image(tmp_path / "layered.exr", image, metadata={"wgputrace:spp": "4"}, layers=layers)
    np.testing.assert_array_equal(load_image(path), image)
    back = load_layers(path)
    assert sorted(back) == sorted(LAYERS)
    for name in LAYERS:
        np.testing.assert_array_equal(back[name], layers[name])
    with OpenEXR.File(str(path), header_only=True) as exr:
        channels = {channel.name for channel in exr.header()["channels"]}
    assert channels == {"R", "G", "B", *(f"{name}.{letter}" for name in LAYERS for letter in "RGB")}
    assert load_layers(save_image(tmp_path / "plain.exr", image)) == {}


def test_layers_are_refused_where_they_cannot_go(tmp_path, rng):
    image = rng.random((5, 7, 3), dtype=np.float32)
    with pytest.raises(ValueError, match=r"only \.exr files carry layers \(raw\)"):
        save_image(tmp_path / "out.png", image, layers={"raw": image})
    with pytest.raises(ValueError, match=r"layer 'raw' has shape \(5, 6, 3\) but the image \(5, 7, 3\)"):
        save_image(tmp_path / "out.exr", image, layers={"raw": image[:, :6]})
    with pytest.raises(ValueError, match="layer name 'a b'"):
        save_image(tmp_path / "out.exr", image, layers={"a b": image})
    assert not any(tmp_path.iterdir())
