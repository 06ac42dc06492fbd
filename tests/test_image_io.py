"""Image files: linear formats round-trip exactly, PNG is clipped sRGB, metadata comes back as\nwritten, and a write is whole or leaves the old file."""

from __future__ import annotations

import json
import stat

import numpy as np
import pytest

from wgputrace import image_io, load_image, save_image
from wgputrace.image_io import FORMATS, linear_to_srgb, read_text_metadata, sidecar_path, srgb8, tonemap


def test_linear_formats_round_trip(tmp_path, rng):
    image = rng.exponential(2.0, (5, 7, 3)).astype(np.float32)
    for suffix in (".exr", ".npy"):
        np.testing.assert_array_equal(load_image(save_image(tmp_path / f"x{suffix}", image)), image)


def test_png_is_srgb_encoded_and_clipped(tmp_path):
    image = np.array([[[0.0, 0.5, 4.0], [0.0031308, 0.2, 1.0]]], dtype=np.float32)
    pixels = srgb8(tonemap(image))
    assert pixels[0, 0].tolist() == [0, 188, 255]  # sRGB(0.5) = 0.7354
    decoded = load_image(save_image(tmp_path / "x.png", image))
    np.testing.assert_allclose(decoded, np.minimum(image, 1.0), atol=0.01)
    assert linear_to_srgb(np.array(1.0)) == pytest.approx(1.0)


def test_nan_never_reaches_a_png():
    pixels = srgb8(tonemap(np.array([[[np.nan, np.inf, -1.0]]], dtype=np.float32)))
    assert pixels.tolist() == [[[0, 255, 0]]]


def test_unknown_format_is_named(tmp_path):
    with pytest.raises(ValueError, match=r"unknown image format '\.tif'"):
        save_image(tmp_path / "x.tif", np.zeros((2, 2, 3), np.float32))
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        save_image(tmp_path / "x.npy", np.zeros((2, 2), np.float32))


# Text outside Latin-1 too: PNG stores it as iTXt, EXR and the sidecar as UTF-8.
METADATA = {"wgputrace:spp": "64", "wgputrace:scene": "sc\u00e8ne \u2192 \u0441\u0446\u0435\u043d\u0430.glb"}


def leftover_temporaries(folder):
    return sorted(path.name for path in folder.iterdir() if path.name.endswith(image_io.TEMPORARY_SUFFIX))


@pytest.mark.parametrize("suffix", FORMATS)
def test_metadata_round_trips(tmp_path, suffix):
    path = save_image(tmp_path / f"x{suffix}", np.ones((2, 3, 3), np.float32), metadata=METADATA)
    text = read_text_metadata(path)
    assert {key: text[key] for key in METADATA} == METADATA
    if suffix == ".npy":
        assert json.loads(sidecar_path(path).read_text(encoding="utf-8")) == METADATA
        assert sidecar_path(path).name == "x.npy.json"
    assert leftover_temporaries(tmp_path) == []


def test_an_npy_saved_without_metadata_loses_its_old_sidecar(tmp_path):
    path = save_image(tmp_path / "x.npy", np.ones((2, 2, 3), np.float32), metadata=METADATA)
    save_image(path, np.zeros((2, 2, 3), np.float32))
    assert not sidecar_path(path).exists()
    assert read_text_metadata(path) == {}


def test_metadata_must_be_text_and_leave_the_exr_header_alone(tmp_path):
    image = np.zeros((2, 2, 3), np.float32)
    with pytest.raises(ValueError, match=r"x\.png: metadata must map str to str, got 'spp': 64"):
        save_image(tmp_path / "x.png", image, metadata={"spp": 64})
    with pytest.raises(ValueError, match=r"x\.exr: metadata key 'compression' is an attribute the EXR header sets"):
        save_image(tmp_path / "x.exr", image, metadata={"compression": "none"})
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("suffix", FORMATS)
def test_an_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch, suffix):
    target = save_image(tmp_path / f"x{suffix}", np.full((4, 4, 3), 0.25, np.float32), metadata=METADATA)
    before = {path.name: path.read_bytes() for path in tmp_path.iterdir()}
    written = image_io._WRITERS[suffix]
    temporaries = []

    def interrupted(path, image, exposure, metadata):
        temporaries.append(path)
        written(path, image, exposure, metadata)
        with open(path, "r+b") as file:  # half the file is on disk when Ctrl-C comes
            file.truncate(path.stat().st_size // 2)
        raise KeyboardInterrupt

    monkeypatch.setitem(image_io._WRITERS, suffix, interrupted)
    with pytest.raises(KeyboardInterrupt):
        save_image(target, np.full((8, 8, 3), 0.5, np.float32), metadata={"wgputrace:spp": "1"})
    assert [path.parent for path in temporaries] == [tmp_path]
    assert temporaries[0].name.startswith(f".{target.name}.")  # hidden, and says whose it is
    assert {path.name: path.read_bytes() for path in tmp_path.iterdir()} == before
    assert leftover_temporaries(tmp_path) == []


@pytest.mark.parametrize("suffix", FORMATS)
def test_a_new_file_replaces_the_old_one_whole_with_ordinary_permissions(tmp_path, suffix):
    old, new = np.full((16, 16, 3), 0.25, np.float32), np.full((2, 3, 3), 0.5, np.float32)
    target = save_image(tmp_path / f"x{suffix}", old)
    assert save_image(target, new, metadata=METADATA) == target
    assert load_image(target).shape == new.shape
    assert leftover_temporaries(tmp_path) == []
    # the mode any new file gets here (umask applied), not a temporary file's private 0o600
    (tmp_path / "plain").touch()
    assert stat.S_IMODE(target.stat().st_mode) == stat.S_IMODE((tmp_path / "plain").stat().st_mode)


def test_reading_metadata_names_the_file_and_the_problem(tmp_path):
    with pytest.raises(ValueError, match=r"absent\.exr: no such file"):
        read_text_metadata(tmp_path / "absent.exr")
    for suffix in (".png", ".exr"):
        (tmp_path / f"junk{suffix}").write_bytes(b"not an image")
        with pytest.raises(ValueError, match=rf"junk\{suffix}: not a readable {suffix[1:].upper()} file"):
            read_text_metadata(tmp_path / f"junk{suffix}")
    path = save_image(tmp_path / "x.npy", np.zeros((2, 2, 3), np.float32))
    sidecar_path(path).write_text("[1, 2]")
    with pytest.raises(ValueError, match=r"x\.npy\.json: expected a JSON object of strings"):
        read_text_metadata(path)


def test_an_npy_interrupted_between_its_renames_has_no_metadata_rather_than_wrong(tmp_path, monkeypatch):
    old = np.full((2, 2, 3), 0.25, np.float32)
    path = save_image(tmp_path / "x.npy", old, metadata=METADATA)

    def interrupted(source, target):
        raise KeyboardInterrupt

    monkeypatch.setattr(image_io.os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        save_image(path, np.ones((2, 2, 3), np.float32), metadata={"wgputrace:spp": "1"})
    np.testing.assert_array_equal(load_image(path), old)
    assert read_text_metadata(path) == {}
    assert leftover_temporaries(tmp_path) == []
