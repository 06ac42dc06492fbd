"""glTF's KHR_materials_clearcoat and KHR_materials_sheen mapped to Principled's clearcoat and sheen
(`gltf_material_lobes`): the factors read, the coat's roughness to Mitsuba's gloss, the fields
Principled lacks ignored with a warning naming them, bad values a SceneLoadError naming the JSON
path; and the material extensions we do not read named in one warning per file."""

from __future__ import annotations

import warnings

import pytest

from wgputrace import Principled, SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.loaders.gltf_material_lobes import clearcoat_gloss
from wgputrace.testing.gltf_files import textured_square, write_glb

COATED = {"KHR_materials_clearcoat": {"clearcoatFactor": 0.6, "clearcoatRoughnessFactor": 0.2}}
VELVET = {"KHR_materials_sheen": {"sheenColorFactor": [0.7, 0.7, 0.7], "sheenRoughnessFactor": 0.5}}


def square_file(tmp_path, extensions: dict, used: list[str] | None = None):
    """A square of an untextured material with `extensions`, which the file lists as used."""
    document, blob = textured_square(
        material={"pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": extensions}
    )
    document["extensionsUsed"] = list(extensions) if used is None else used
    return write_glb(tmp_path / "square.glb", document, blob)


def material_of(path) -> Principled:
    (shape,) = load_scene(path).shapes
    return shape.material


def test_clearcoat_and_sheen_make_a_principled_without_warnings(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coated = material_of(square_file(tmp_path, COATED))
        velvet = material_of(square_file(tmp_path, VELVET))
    assert isinstance(coated, Principled) and coated.lobes() == {"clearcoat"}
    assert coated.clearcoat == pytest.approx(0.6)
    # glTF's coat alpha 0.2^2 = 0.04 is Mitsuba's GTR1 alpha lerp(0.1, 0.001, gloss)
    assert 0.1 + (0.001 - 0.1) * coated.clearcoat_gloss == pytest.approx(0.04)
    assert isinstance(velvet, Principled) and velvet.lobes() == {"sheen"}
    assert (velvet.sheen, velvet.sheen_tint) == (pytest.approx(0.7), 0.0)


def test_the_coat_roughness_keeps_its_alpha_within_mitsubas_range():
    assert clearcoat_gloss(0.0) == 1.0  # glTF's mirror coat: Mitsuba's glossiest, alpha 0.001
    assert clearcoat_gloss(0.1) == pytest.approx(0.9 / 0.99)
    assert clearcoat_gloss(0.5) == 0.0  # rougher than alpha 0.1: Mitsuba's roughest


def test_fields_principled_lacks_are_named_in_a_warning(tmp_path):
    textured = {
        "KHR_materials_clearcoat": {
            "clearcoatFactor": 1.0,
            "clearcoatTexture": {"index": 0},
            "clearcoatNormalTexture": {"index": 0},
        },
        "KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.2, 0.2], "sheenRoughnessTexture": {"index": 0}},
    }
    with pytest.warns(SceneLoadWarning) as caught:
        material = material_of(square_file(tmp_path, textured))
    messages = "\n".join(str(w.message) for w in caught)
    assert "materials[0].extensions.KHR_materials_clearcoat: clearcoatTexture, clearcoatNormalTexture ignored" in (
        messages
    )
    assert "materials[0].extensions.KHR_materials_sheen: sheenRoughnessTexture ignored" in messages
    assert "sheenColorFactor [1.0, 0.2, 0.2]" in messages and material.sheen == 1.0


@pytest.mark.parametrize(
    "extensions, where",
    [
        ({"KHR_materials_clearcoat": {"clearcoatFactor": 1.5}}, "KHR_materials_clearcoat.clearcoatFactor"),
        ({"KHR_materials_clearcoat": {"clearcoatRoughnessFactor": -1}}, "KHR_materials_clearcoat.clearcoatRoughness"),
        ({"KHR_materials_sheen": {"sheenColorFactor": [2, 0, 0]}}, "KHR_materials_sheen.sheenColorFactor"),
        ({"KHR_materials_sheen": {"sheenColorFactor": [1, 0]}}, "KHR_materials_sheen"),
    ],
)
def test_bad_values_are_one_line_errors(tmp_path, extensions, where):
    with pytest.raises(SceneLoadError, match=rf"square\.glb: materials\[0\]\.extensions\.{where}") as error:
        load_scene(square_file(tmp_path, extensions))
    assert "\n" not in str(error.value)


def test_unread_material_extensions_are_named_in_one_warning_per_file(tmp_path):
    used = ["KHR_materials_specular", "KHR_materials_dispersion", "KHR_materials_clearcoat"]
    extensions = COATED | {"KHR_materials_specular": {"specularFactor": 0.5}, "KHR_materials_dispersion": {}}
    with pytest.warns(SceneLoadWarning) as caught:
        material_of(square_file(tmp_path, extensions, used))
    (warning,) = caught
    assert "KHR_materials_specular (specular strength and colour: Mitsuba's spec_tint" in str(warning.message)
    assert "KHR_materials_dispersion" in str(warning.message)
    assert "KHR_materials_clearcoat" not in str(warning.message)
