"""glTF materials with textures: pbrMetallicRoughness with its textures becomes a Principled whose
textures hold the file's images (embedded in the .glb, as data URIs, or files beside it), in the
orientation and colour space glTF defines; samplers and KHR_texture_transform are read; the
shape gets the file's TEXCOORD_0; and every bad image is a one-line SceneLoadError naming the file,
the JSON path and the problem."""

from __future__ import annotations

import copy
import io
import math
import warnings

import numpy as np
import pytest
from PIL import Image

from wgputrace import Emitter, Principled, SceneLoadError, SceneLoadWarning, load_scene, render
from wgputrace.testing.gltf_files import (
    SQUARE_UVS,
    TEXTURED_MATERIAL,
    light_node,
    png_bytes,
    png_header,
    textured_square,
    with_lights,
    write_glb,
    write_gltf,
)

RED_TOP_LEFT = (1.0, 0.0, 0.0, 1.0)
GREY_SRGB_128 = ((128 / 255 + 0.055) / 1.055) ** 2.4  # mid-grey 128 decoded from sRGB


def load_quiet(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SceneLoadWarning)  # the parameters Principled lacks so far
        return load_scene(path)


@pytest.mark.parametrize("how", ["bufferView", "data", "file"])
def test_base_color_texture_from_every_storage_with_uvs(tmp_path, how):
    document, blob = textured_square(how, tmp_path)
    writer = write_glb if how == "bufferView" else write_gltf
    (shape,) = load_quiet(
        writer(tmp_path / f"square_{how}.gl{'b' if how == 'bufferView' else 'tf'}", document, blob)
    ).shapes
    material = shape.material
    assert isinstance(material, Principled) and not isinstance(material, Emitter)
    assert (material.base_color, material.alpha) == ((1.0, 0.5, 0.5), pytest.approx(0.8))
    assert (material.metallic, material.roughness, material.eta) == (0.25, 0.75, 1.4)
    texels = material.base_color_texture.linear_texels
    np.testing.assert_allclose(texels[0, 0], RED_TOP_LEFT)  # row 0 is the image's top
    np.testing.assert_allclose(texels[1, 1, :3], GREY_SRGB_128, rtol=1e-5)  # sRGB decoded
    assert texels[-1, -1, 3] == 0.0  # alpha kept, linear
    assert (material.base_color_texture.wrap_s, material.base_color_texture.wrap_t) == ("clamp", "mirror")
    np.testing.assert_array_equal(shape.uvs, SQUARE_UVS[[[0, 1, 2], [0, 2, 3]]])


@pytest.mark.gpu
def test_the_marked_corner_renders_at_the_top_left(gpu_context, tmp_path):
    """Seen from +z as glTF frames it, the square's top-left corner shows the texture's red texel."""
    material = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}
    document, blob = textured_square(material=material)
    document = with_lights(document, [{"type": "directional", "intensity": 3}], [light_node(0)])
    image = render(load_quiet(write_glb(tmp_path / "lit.glb", document, blob)), 16, 16, 16, seed=3)
    redness = image[..., 0] - image[..., 1]
    top_left, bottom_right = redness[2:6, 2:6].mean(), redness[10:14, 10:14].mean()
    assert top_left > 0.1 and abs(bottom_right) < 0.02, (top_left, bottom_right)


def test_metallic_roughness_texture_is_linear_with_its_transform(tmp_path):
    material = load_quiet(write_glb(tmp_path / "square.glb", *textured_square())).shapes[0].material
    texture = material.metallic_roughness_texture
    assert not texture.srgb
    np.testing.assert_allclose(texture.linear_texels[1, 1, :3], 128 / 255)
    assert (texture.transform.offset, texture.transform.rotation, texture.transform.scale) == (
        (0.5, 0.0),
        0.5,
        (2.0, 3.0),
    )
    assert material.base_color_texture.transform.scale == (1.0, 1.0)  # the transform is per texture use


def test_an_emissive_texture_does_not_make_a_uniform_emitter(tmp_path):
    """DamagedHelmet: emissiveFactor (1, 1, 1) with an emissiveTexture is a textured Principled."""
    material = dict(copy.deepcopy(TEXTURED_MATERIAL))
    material["pbrMetallicRoughness"] = {}
    material.pop("normalTexture"), material.pop("alphaMode")
    shape = load_quiet(write_glb(tmp_path / "helmet.glb", *textured_square(material=material))).shapes[0]
    assert isinstance(shape.material, Principled)
    if hasattr(shape.material, "emission_texture"):
        assert shape.material.emission_texture is not None and shape.material.emission == (1.0, 1.0, 1.0)


def test_an_untextured_material_keeps_its_mapping_and_shape_no_uvs(tmp_path):
    material = {"emissiveFactor": [1, 1, 1], "pbrMetallicRoughness": {"metallicFactor": 0}}
    shape = load_quiet(write_glb(tmp_path / "lamp.glb", *textured_square(material=material))).shapes[0]
    assert isinstance(shape.material, Emitter)
    assert shape.uvs is None  # the file's TEXCOORD_0 is not uploaded for a material without textures


def test_transmission_is_principled_spec_trans_its_texture_ignored_with_a_warning(tmp_path):
    material = copy.deepcopy(TEXTURED_MATERIAL)
    material["extensions"]["KHR_materials_transmission"] = {
        "transmissionFactor": 0.7,
        "transmissionTexture": {"index": 0},
    }
    with pytest.warns(
        SceneLoadWarning, match=r"materials\[0\]\.extensions\.KHR_materials_transmission\.transmissionTexture"
    ):
        shape = load_scene(write_glb(tmp_path / "glass.glb", *textured_square(material=material))).shapes[0]
    assert isinstance(shape.material, Principled)
    assert (shape.material.spec_trans, shape.material.eta) == (pytest.approx(0.7), 1.4)
    assert shape.material.base_color_texture is not None  # textures kept


def test_one_image_is_one_texture_for_uses_alike(tmp_path):
    document, blob = textured_square()
    document["materials"].append(copy.deepcopy(TEXTURED_MATERIAL))
    document["meshes"].append(copy.deepcopy(document["meshes"][0]))
    document["meshes"][1]["primitives"][0]["material"] = 1
    document["nodes"].append({"mesh": 1})
    document["scenes"][0]["nodes"].append(1)
    first, second = (s.material for s in load_quiet(write_glb(tmp_path / "two.glb", document, blob)).shapes)
    assert first is not second and first.base_color_texture is second.base_color_texture


def test_normalized_byte_texcoords_and_a_second_uv_set(tmp_path):
    document, blob = textured_square()
    accessor = document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
    view = document["bufferViews"][document["accessors"][accessor]["bufferView"]]
    data = bytearray(blob)
    data[view["byteOffset"] : view["byteOffset"] + 8] = bytes([0, 255, 255, 255, 255, 0, 0, 0])
    view["byteLength"] = 8
    document["accessors"][accessor].update(componentType=5121, normalized=True)
    document["materials"][0]["normalTexture"]["texCoord"] = 1
    with pytest.warns(SceneLoadWarning, match=r"normalTexture.texCoord: only TEXCOORD_0 is read"):
        shape = load_scene(write_glb(tmp_path / "bytes.glb", document, bytes(data))).shapes[0]
    np.testing.assert_array_equal(shape.uvs, SQUARE_UVS[[[0, 1, 2], [0, 2, 3]]])


def image_entry(document: dict, blob: bytes, data: bytes) -> tuple[dict, bytes]:
    """`document` whose image 0 is `data` as a data URI."""
    import base64

    document["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(data).decode()}]
    return document, blob


def jpeg_with_height(height: int) -> bytes:
    """A 5 x 3 JPEG whose frame header claims `height` rows."""
    stream = io.BytesIO()
    Image.fromarray(np.zeros((3, 5, 3), np.uint8)).save(stream, format="JPEG")
    data = bytearray(stream.getvalue())
    frame = data.find(b"\xff\xc0")
    data[frame + 5 : frame + 7] = height.to_bytes(2, "big")
    return bytes(data)


BAD_IMAGES = {
    "corrupt PNG": (lambda png: png[: len(png) // 2], r"images\[0\].uri: not a readable image"),
    "not an image": (lambda png: b"hello, world", r"images\[0\].uri: not an image Pillow reads"),
    "zero pixels": (lambda png: png_header(0, 4), r"images\[0\].uri: 0 x 4 pixels: each side must be 1 to 65,536"),
    "100,000 pixels": (
        lambda png: png_header(100_000, 100_000),
        r"images\[0\].uri: 100000 x 100000 pixels: each side must be 1 to 65,536",
    ),
    "a JPEG of 0 rows": (lambda png: jpeg_with_height(0), r"images\[0\].uri: 5 x 0 pixels"),
    "corrupt JPEG": (lambda png: jpeg_with_height(3)[:-200], r"images\[0\].uri: not a readable image"),
}


@pytest.mark.parametrize("case", BAD_IMAGES, ids=list(BAD_IMAGES))
def test_bad_images_are_one_line_errors(tmp_path, case):
    change, message = BAD_IMAGES[case]
    document, blob = textured_square("data")
    good = png_bytes(np.random.default_rng(1).integers(0, 256, (16, 16, 3), dtype=np.uint8))
    path = write_glb(tmp_path / "bad.glb", *image_entry(document, blob, change(good)))
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(path)
    assert str(caught.value).startswith(f"{path}: ") and "\n" not in str(caught.value)


BAD_FIELDS = {
    "missing file": (lambda d: d["images"][0].update(uri="nowhere.png"), r"images\[0\].uri: cannot read .*nowhere.png"),
    "bad data URI": (lambda d: d["images"][0].update(uri="data:image/png;base64,@@"), r"images\[0\].uri: data URI"),
    "image index": (lambda d: d["textures"][0].update(source=7), r"images index 7 out of range"),
    "texture index": (
        lambda d: d["materials"][0]["normalTexture"].update(index=3),
        r"materials\[0\].normalTexture.index: textures index 3 out of range",
    ),
    "WebP only": (
        lambda d: d["textures"][0].update(source=None, extensions={"EXT_texture_webp": {"source": 0}}),
        r"textures\[0\]: its image is only given as EXT_texture_webp \(WebP\), which is not decoded here$",
    ),
    "wrap mode": (lambda d: d["samplers"][0].update(wrapS=1), r"samplers\[0\].wrapS: must be 10497, 33071 or 33648"),
    "textureInfo": (
        lambda d: d["materials"][0].update(emissiveTexture=5),
        r"materials\[0\].emissiveTexture: must be an object",
    ),
    "alphaMode": (lambda d: d["materials"][0].update(alphaMode="CLIP"), r"materials\[0\].alphaMode: must be one of"),
    "transform": (
        lambda d: d["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"]["extensions"][
            "KHR_texture_transform"
        ].update(scale=[1, math.inf]),
        r"KHR_texture_transform.scale: must be finite",
    ),
    "bufferView": (lambda d: d["images"][0].update(uri=None, bufferView=40), r"bufferViews index 40 out of range"),
}


@pytest.mark.parametrize("case", BAD_FIELDS, ids=list(BAD_FIELDS))
def test_bad_texture_fields_are_one_line_errors(tmp_path, case):
    change, message = BAD_FIELDS[case]
    document, blob = textured_square("data")
    change(document)
    for entry in document["images"] + document["textures"]:
        for key in [k for k, v in entry.items() if v is None]:
            del entry[key]
    path = write_glb(tmp_path / "bad.glb", document, blob)
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_quiet(path)
    assert str(caught.value).startswith(f"{path}: ") and "\n" not in str(caught.value)


def test_texcoords_of_another_length_are_an_error(tmp_path):
    document, blob = textured_square()
    accessor = document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
    document["accessors"][accessor]["count"] = 3
    with pytest.raises(SceneLoadError, match=r"attributes.TEXCOORD_0: has 3 values for 4 positions"):
        load_quiet(write_glb(tmp_path / "short.glb", document, blob))


def test_opaque_ignores_the_base_colour_alpha(tmp_path):
    material = copy.deepcopy(TEXTURED_MATERIAL)
    del material["alphaMode"]
    assert (
        load_quiet(write_glb(tmp_path / "opaque.glb", *textured_square(material=material))).shapes[0].material.alpha
        == 1.0
    )
