"""glTF's KHR_materials_anisotropy mapped to Principled's anisotropic and anisotropy_rotation
(`gltf_anisotropy`): glTF's alpha ratio alpha_t / alpha_b kept as Mitsuba's alpha_u / alpha_v at the
material's roughness, the rotation read, the primitive's texture coordinates and TANGENT read for
the frame, the texture ignored with one warning per file, bad values a SceneLoadError naming the
JSON path."""

from __future__ import annotations

import math
import warnings

import pytest

from wgputrace import Principled, SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.loaders.gltf_anisotropy import ANISOTROPY, anisotropic_from_strength
from wgputrace.testing.gltf_files import textured_square, write_glb

ROUGHNESS = 0.4


def square_file(tmp_path, anisotropy: dict, materials: int = 1, roughness: float = ROUGHNESS):
    """A square of an untextured metal with KHR_materials_anisotropy `anisotropy`, and `materials`
    copies of that material, a primitive of the square on each."""
    material = {"pbrMetallicRoughness": {"roughnessFactor": roughness}, "extensions": {ANISOTROPY: anisotropy}}
    document, blob = textured_square(material=material)
    document["materials"] *= materials
    document["meshes"][0]["primitives"] += [
        dict(document["meshes"][0]["primitives"][0], material=i) for i in range(1, materials)
    ]
    document["extensionsUsed"] = [ANISOTROPY]
    return write_glb(tmp_path / "square.glb", document, blob)


def mitsuba_alphas(material: Principled) -> tuple[float, float]:
    """Mitsuba's calc_dist_params: (alpha_u, alpha_v)."""
    aspect = math.sqrt(1.0 - 0.9 * material.anisotropic)
    alpha = material.roughness**2
    return max(0.001, alpha / aspect), max(0.001, alpha * aspect)


def test_strength_and_rotation_are_read_with_glTFs_alpha_ratio(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        (shape,) = load_scene(square_file(tmp_path, {"anisotropyStrength": 0.5, "anisotropyRotation": 1.0})).shapes
    material = shape.material
    assert isinstance(material, Principled) and material.lobes() == {"anisotropic"}
    assert material.anisotropy_rotation == pytest.approx(1.0)
    alpha = ROUGHNESS**2
    alpha_t = alpha + (1.0 - alpha) * 0.5**2
    alpha_u, alpha_v = mitsuba_alphas(material)
    assert alpha_u / alpha_v == pytest.approx(alpha_t / alpha, rel=1e-9)
    # the frame's tangent: the file's TANGENT, with the texture coordinates it goes with
    assert shape.tangents is not None and shape.uvs is not None


def test_no_strength_is_no_anisotropy_and_rotations_wrap(tmp_path):
    # a metal without anisotropy maps as it does without the extension
    (shape,) = load_scene(square_file(tmp_path, {"anisotropyRotation": 2.0})).shapes
    assert not isinstance(shape.material, Principled)
    (shape,) = load_scene(square_file(tmp_path, {"anisotropyStrength": 0.2, "anisotropyRotation": 7.0})).shapes
    assert shape.material.anisotropy_rotation == pytest.approx(7.0 - 2.0 * math.pi)


def test_a_ratio_past_mitsubas_is_cut_with_a_warning(tmp_path):
    assert anisotropic_from_strength(1.0, 0.1) > 1.0  # glTF's ratio 100 against Mitsuba's 10
    assert anisotropic_from_strength(1.0, ROUGHNESS) < 1.0  # 6.25
    with pytest.warns(SceneLoadWarning, match=r"anisotropyStrength 1 at roughness 0.2 .* anisotropic 1"):
        (shape,) = load_scene(square_file(tmp_path, {"anisotropyStrength": 1.0}, roughness=0.2)).shapes
    assert shape.material.anisotropic == 1.0


def test_the_texture_is_ignored_with_one_warning_per_file(tmp_path):
    textured = {"anisotropyStrength": 0.3, "anisotropyTexture": {"index": 0}}
    with pytest.warns(SceneLoadWarning) as caught:
        shapes = load_scene(square_file(tmp_path, textured, materials=2)).shapes
    assert len(shapes) == 2 and all(shape.material.anisotropic > 0 for shape in shapes)
    (warning,) = [w for w in caught if "anisotropyTexture" in str(w.message)]
    assert f"materials[0].extensions.{ANISOTROPY}.anisotropyTexture ignored" in str(warning.message)


@pytest.mark.parametrize(
    "anisotropy, where",
    [
        ({"anisotropyStrength": 1.5}, "anisotropyStrength: must be in"),
        ({"anisotropyStrength": "strong"}, "anisotropyStrength: must be float"),
        ({"anisotropyStrength": 0.5, "anisotropyRotation": 1e400}, "anisotropyRotation: must be a finite"),
    ],
)
def test_bad_values_are_one_line_errors(tmp_path, anisotropy, where):
    with pytest.raises(SceneLoadError, match=rf"square\.glb: materials\[0\]\.extensions\.{ANISOTROPY}\.{where}") as e:
        load_scene(square_file(tmp_path, anisotropy))
    assert "\n" not in str(e.value)
