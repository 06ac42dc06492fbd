"""KHR_texture_basisu: KTX2 textures made here with basis_universal's encoder (alktx2) load through
opengl-basisu (the `ktx2` extra) in both codecs, sRGB or linear as their slot says; without the
extra they are refused naming it; a corrupt KTX2 is a one-line SceneLoadError naming the file, the
JSON path and the problem."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

from wgputrace import SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.loaders.ktx2_images import KTX2_IDENTIFIER
from wgputrace.testing.gltf_files import write_glb
from wgputrace.testing.ktx2_files import CODECS, encode_ktx2, ktx2_textured_square

SIZE = 64
# Peak signal-to-noise ratio (dB over all four channels) the codecs keep on `smooth_pixels`.
# basis_universal states typical quality, not a bound: ETC1S (one colour per 4x4 block and
# luminance steps) reaches 32.2 dB here (33.2 linear), UASTC 43.8; the encoder is deterministic,
# and a flipped axis or swapped channels score about 10 dB.
MIN_PSNR = {"etc1s": 30.0, "uastc": 42.0}
INSTALL = 'pip install "wgputrace[ktx2]"'


@pytest.fixture
def codecs():
    """The transcoder (the `ktx2` extra) and the encoder that makes the test files (the test extra)."""
    pytest.importorskip("opengl_basisu")
    pytest.importorskip("alktx2")


def smooth_pixels() -> np.ndarray:
    """SIZE x SIZE RGBA of smooth ramps, different along each axis and in each channel."""
    y, x = np.mgrid[0:SIZE, 0:SIZE] / SIZE
    channels = [0.5 + 0.5 * np.sin(6 * x + 1), 0.5 + 0.5 * np.cos(5 * y), x * y, 0.6 + 0.4 * x]
    return np.rint(np.stack(channels, -1) * 255).astype(np.uint8)


def psnr(decoded: np.ndarray, original: np.ndarray) -> float:
    error = np.mean((decoded.astype(np.float64) - original) ** 2)
    return float(10 * np.log10(255.0**2 / error))


def load_quiet(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SceneLoadWarning)  # TEXTURED_MATERIAL's occlusion texture
        return load_scene(path)


def ktx2_glb(path, ktx2: bytes, **changes):
    document, blob = ktx2_textured_square(ktx2)
    document.update(changes)
    return write_glb(path, document, blob)


@pytest.mark.parametrize("codec", CODECS)
@pytest.mark.parametrize("file_srgb", [True, False], ids=["sRGB file", "linear file"])
def test_ktx2_texels_round_trip_within_the_codec_in_the_slots_colour_space(tmp_path, codecs, codec, file_srgb):
    pixels = smooth_pixels()
    (shape,) = load_quiet(ktx2_glb(tmp_path / "square.glb", encode_ktx2(pixels, codec, file_srgb))).shapes
    material = shape.material
    base, metal_rough = material.base_color_texture, material.metallic_roughness_texture
    assert psnr(base.encoded_texels, pixels) >= MIN_PSNR[codec]
    np.testing.assert_array_equal(metal_rough.encoded_texels, base.encoded_texels)  # one image decoded once
    # the slot decides, whatever the file's header declares
    assert (base.srgb, metal_rough.srgb, material.normal_texture.srgb) == (True, False, False)


def test_a_png_source_beside_the_ktx2_one_is_read(tmp_path, codecs):
    pixels = smooth_pixels()
    document, blob = ktx2_textured_square(encode_ktx2(pixels, "etc1s", True))
    document["images"].append({"uri": "missing.png"})
    document["textures"][0]["source"] = 1
    with pytest.raises(SceneLoadError, match=r"images\[1\].uri: cannot read .*missing.png"):
        load_quiet(write_glb(tmp_path / "fallback.glb", document, blob))


def test_without_opengl_basisu_a_ktx2_texture_is_refused_naming_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "opengl_basisu", None)  # `import opengl_basisu` then raises ImportError
    ktx2 = KTX2_IDENTIFIER + bytes(68)  # refused before anything decodes it
    required = ktx2_glb(tmp_path / "required.glb", ktx2)
    with pytest.raises(SceneLoadError) as caught:
        load_quiet(required)
    assert str(caught.value) == (
        f"{required}: extensionsRequired: not supported here: "
        f"KHR_texture_basisu (KTX2 textures): needs opengl-basisu: {INSTALL}"
    )
    used = ktx2_glb(tmp_path / "used.glb", ktx2, extensionsRequired=[])
    with pytest.raises(SceneLoadError) as caught:
        load_quiet(used)
    assert str(caught.value) == (
        f"{used}: textures[0]: its image is only given as KHR_texture_basisu (KTX2/BasisU), "
        f"which is not decoded here (KTX2 needs opengl-basisu: {INSTALL})"
    )


def corrupted(ktx2: bytes) -> bytes:
    """`ktx2` with its level index pointing past the end of the file."""
    data = bytearray(ktx2)
    level_offset = 80  # the first level's byteOffset (KTX2 spec 3.9: after the 80-byte header)
    data[level_offset : level_offset + 8] = (len(ktx2) * 2).to_bytes(8, "little")
    return bytes(data)


BAD_KTX2 = {
    "truncated": (lambda ktx2: ktx2[: len(ktx2) // 2], r"not a readable KTX2/Basis Universal image: "),
    "header only": (lambda ktx2: ktx2[:20], r"not a readable KTX2/Basis Universal image: truncated"),
    "level past the end": (corrupted, r"not a readable KTX2/Basis Universal image: "),
    "100,000 pixels": (
        lambda ktx2: ktx2[:20] + (100_000).to_bytes(4, "little") * 2 + ktx2[28:],
        r"100000 x 100000 pixels: each side must be 1 to 65,536",
    ),
}


@pytest.mark.parametrize("case", BAD_KTX2, ids=list(BAD_KTX2))
@pytest.mark.parametrize("codec", CODECS)
def test_a_corrupt_ktx2_is_a_one_line_error_naming_file_path_and_problem(tmp_path, codecs, case, codec):
    change, problem = BAD_KTX2[case]
    path = ktx2_glb(tmp_path / "bad.glb", change(encode_ktx2(smooth_pixels(), codec, True)))
    with pytest.raises(SceneLoadError, match=problem) as caught:
        load_quiet(path)
    message = str(caught.value)
    assert message.startswith(f"{path}: images[0].bufferView: ") and "\n" not in message


def test_a_bad_basisu_source_names_its_json_path(tmp_path, codecs):
    document, blob = ktx2_textured_square(encode_ktx2(smooth_pixels(), "etc1s", True))
    document["textures"][0]["extensions"]["KHR_texture_basisu"]["source"] = 5
    path = write_glb(tmp_path / "bad.glb", document, blob)
    with pytest.raises(SceneLoadError) as caught:
        load_quiet(path)
    assert str(caught.value) == (
        f"{path}: textures[0].extensions.KHR_texture_basisu.source: images index 5 out of range (1 images)"
    )
