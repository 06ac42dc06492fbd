"""glTF's KHR_materials_pbrSpecularGlossiness converted to metallic-roughness
(`gltf_specular_glossiness`): a dielectric keeps its diffuse colour as base colour, a metal's
specular colour becomes its base colour at metallic 1, glossiness becomes 1 - roughness, the
diffuse texture the base colour texture; one warning per file says so, and bad values are a
SceneLoadError naming the JSON path."""

from __future__ import annotations

import pytest

from wgputrace import Diffuse, Glossy, Principled, SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.loaders.gltf_specular_glossiness import SPECULAR_GLOSSINESS, metallic_roughness
from wgputrace.testing.gltf_files import SQUARE, SQUARE_INDICES, gltf_document, textured_square, write_glb

PLASTIC = {"diffuseFactor": [0.5, 0.25, 0.1, 1.0], "specularFactor": [0.04, 0.04, 0.04], "glossinessFactor": 0.7}
GOLD = {"diffuseFactor": [0.0, 0.0, 0.0, 1.0], "specularFactor": [1.0, 0.8, 0.3], "glossinessFactor": 0.9}


def squares_file(tmp_path, blocks: list[dict]):
    """One square per specular-glossiness block, each its own material."""
    document, blob = gltf_document(
        [(SQUARE + [2.0 * i, 0.0, 0.0], SQUARE_INDICES, i) for i in range(len(blocks))],
        materials=[{"extensions": {SPECULAR_GLOSSINESS: block}} for block in blocks],
        extensionsUsed=[SPECULAR_GLOSSINESS],
    )
    return write_glb(tmp_path / "specular.glb", document, blob)


def test_the_conversion_keeps_a_dielectric_and_a_metal():
    plastic, gold = metallic_roughness(PLASTIC), metallic_roughness(GOLD)
    assert plastic["metallicFactor"] == 0.0 and plastic["roughnessFactor"] == pytest.approx(0.3)
    assert plastic["baseColorFactor"] == pytest.approx(PLASTIC["diffuseFactor"])
    assert gold["metallicFactor"] == pytest.approx(1.0) and gold["roughnessFactor"] == pytest.approx(0.1)
    assert gold["baseColorFactor"] == pytest.approx([*GOLD["specularFactor"], 1.0])


def test_materials_are_converted_with_one_warning_per_file(tmp_path):
    with pytest.warns(SceneLoadWarning) as caught:
        plastic, gold = (shape.material for shape in load_scene(squares_file(tmp_path, [PLASTIC, GOLD])).shapes)
    (warning,) = caught
    assert f"{SPECULAR_GLOSSINESS}: materials converted to metallic-roughness" in str(warning.message)
    assert isinstance(plastic, Diffuse) and plastic.color == pytest.approx((0.5, 0.25, 0.1))
    assert isinstance(gold, Glossy) and gold.color == pytest.approx((1.0, 0.8, 0.3))
    assert gold.roughness == pytest.approx(0.1**2)  # glTF's perceptual roughness squared


def test_the_diffuse_texture_is_the_base_colour_texture(tmp_path):
    document, blob = textured_square(
        material={"extensions": {SPECULAR_GLOSSINESS: PLASTIC | {"diffuseTexture": {"index": 0}}}}
    )
    document["extensions"] = {}
    document["extensionsUsed"] = [SPECULAR_GLOSSINESS]
    with pytest.warns(SceneLoadWarning, match="converted"):
        (shape,) = load_scene(write_glb(tmp_path / "textured.glb", document, blob)).shapes
    assert isinstance(shape.material, Principled) and shape.material.base_color_texture is not None
    assert shape.material.base_color == pytest.approx((0.5, 0.25, 0.1))


def test_the_specular_glossiness_texture_is_named_as_ignored(tmp_path):
    with pytest.warns(SceneLoadWarning) as caught:
        load_scene(squares_file(tmp_path, [PLASTIC | {"specularGlossinessTexture": {"index": 0}}]))
    assert any(
        f"materials[0].extensions.{SPECULAR_GLOSSINESS}.specularGlossinessTexture ignored" in str(w.message)
        for w in caught
    )


@pytest.mark.parametrize(
    "block, where",
    [({"glossinessFactor": 2.0}, "glossinessFactor: must be in"), ({"specularFactor": [1, 1]}, "")],
)
def test_bad_values_are_one_line_errors(tmp_path, block, where):
    with pytest.raises(SceneLoadError, match=rf"materials\[0\]\.extensions\.{SPECULAR_GLOSSINESS}.?{where}"):
        load_scene(squares_file(tmp_path, [block]))
