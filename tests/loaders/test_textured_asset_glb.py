"""The built-in `textured_asset` scene's model written as a .glb (`textured_asset_glb`) loads back as
the scene's own shapes and materials: so the Mitsuba comparison of that scene (its reference case)
is one of a textured glTF model with a
normal map and an emissive texture, read by our loader."""

from __future__ import annotations

import warnings

import numpy as np

from wgputrace import load_scene
from wgputrace.scenes.textured_asset import textured_asset
from wgputrace.testing.gltf_files import textured_asset_glb

NUMBERS = ("base_color", "metallic", "roughness", "eta", "normal_scale", "emission", "emission_strength")
CHOICES = ("alpha_mode", "double_sided")
TEXTURES = ("base_color_texture", "metallic_roughness_texture", "normal_texture", "emission_texture")


def test_the_glb_loads_as_the_scenes_model(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loaded = load_scene(textured_asset_glb(tmp_path / "asset.glb"))
    built = textured_asset()
    assert len(loaded.shapes) == len(built.shapes)
    for ours, theirs in zip(built.shapes, loaded.shapes, strict=True):
        np.testing.assert_allclose(theirs.world_vertices, ours.world_vertices, atol=1e-6)
        for corners in ("normals", "uvs"):
            if getattr(ours, corners) is None:
                assert getattr(theirs, corners) is None
            else:
                np.testing.assert_allclose(getattr(theirs, corners), getattr(ours, corners), atol=1e-6)
        assert type(theirs.material) is type(ours.material)
    panel, floor = (shape.material for shape in built.shapes)
    read_panel, read_floor = (shape.material for shape in loaded.shapes)
    assert read_floor.color == floor.color
    for name in NUMBERS:
        np.testing.assert_allclose(getattr(read_panel, name), getattr(panel, name), err_msg=name)
    for name in CHOICES:
        assert getattr(read_panel, name) == getattr(panel, name), name
    for name in TEXTURES:
        mine, read = getattr(panel, name), getattr(read_panel, name)
        assert read.srgb == mine.srgb, name
        np.testing.assert_array_equal(read.encoded_texels, mine.encoded_texels, err_msg=name)
