"""glTF's KHR_materials_volume: attenuationColor and attenuationDistance become a transmitting
Principled's attenuation parameters (its absorption inside) where thicknessFactor makes the mesh a
volume (its value is not needed), a thin wall (thickness 0) or a volume without transmission does
nothing, and a bad value is a one-line SceneLoadError naming the file and
the field's JSON path."""

from __future__ import annotations

import copy
import math
import warnings

import numpy as np
import pytest

from wgputrace import Principled, SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.loaders.gltf_volume import VOLUME_EXTENSION
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, MATERIALS, gltf_document, write_glb

GLASS = MATERIALS[1]  # transmissionFactor 1, ior 1.33
VOLUME_PATH = r"materials\[0\]\.extensions\.KHR_materials_volume"


def volume_box(tmp_path, volume: dict, material: dict = GLASS):
    material = copy.deepcopy(material)
    material.setdefault("extensions", {})[VOLUME_EXTENSION] = volume
    document, blob = gltf_document(
        [(BOX, BOX_INDICES, 0)],
        materials=[material],
        extensionsUsed=[VOLUME_EXTENSION],
        extensionsRequired=[VOLUME_EXTENSION],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", SceneLoadWarning)  # a read extension warns of nothing
        return load_scene(write_glb(tmp_path / "volume.glb", document, blob)).shapes[0].material


def test_attenuation_color_and_distance_become_principled_absorption(tmp_path):
    volume = {"attenuationColor": [0.5, 0.25, 1.0], "attenuationDistance": 2.0, "thicknessFactor": 0.3}
    material = volume_box(tmp_path, volume)
    assert isinstance(material, Principled) and material.spec_trans == 1.0
    assert (material.attenuation_color, material.attenuation_distance) == ((0.5, 0.25, 1.0), 2.0)
    np.testing.assert_allclose(material.absorption(), [math.log(2) / 2, math.log(4) / 2, 0.0])


def test_defaults_absorb_nothing(tmp_path):
    material = volume_box(tmp_path, {"thicknessFactor": 1.0, "thicknessTexture": {"index": 0}})
    assert material.attenuation_distance == math.inf
    assert material.absorption() == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("thickness", [{}, {"thicknessFactor": 0}])
def test_a_thin_wall_absorbs_nothing(tmp_path, thickness):
    material = volume_box(tmp_path, {"attenuationColor": [0.5, 0.5, 0.5], "attenuationDistance": 1.0, **thickness})
    assert material.absorption() == (0.0, 0.0, 0.0)


def test_a_volume_without_transmission_does_nothing(tmp_path):
    opaque = {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0.0}}
    volume = {"attenuationColor": [0.5, 0.5, 0.5], "attenuationDistance": 1.0, "thicknessFactor": 1.0}
    assert volume_box(tmp_path, volume, opaque).absorption() == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    "volume, field, problem",
    [
        ({"attenuationDistance": 0}, "attenuationDistance", "must be > 0, got 0.0"),
        ({"attenuationDistance": -1.5}, "attenuationDistance", "must be > 0, got -1.5"),
        ({"attenuationDistance": "far"}, "attenuationDistance", "must be float"),
        ({"attenuationColor": [0.5, 1.5, 0.5]}, "attenuationColor", r"must be in \[0, 1\]"),
        ({"attenuationColor": [0.5, -0.1, 0.5]}, "attenuationColor", r"must be in \[0, 1\]"),
        ({"attenuationColor": [0.5, 0.5]}, "attenuationColor", "must be 3 numbers"),
        ({"thicknessFactor": -0.1}, "thicknessFactor", "must be >= 0, got -0.1"),
    ],
)
def test_bad_values_name_the_field(tmp_path, volume, field, problem):
    with pytest.raises(SceneLoadError, match=rf"volume\.glb: {VOLUME_PATH}\.{field}: {problem}") as caught:
        volume_box(tmp_path, volume)
    assert "\n" not in str(caught.value)


def test_a_volume_that_is_not_an_object_names_it(tmp_path):
    with pytest.raises(SceneLoadError, match=rf"{VOLUME_PATH}: must be dict"):
        volume_box(tmp_path, [1.0])
