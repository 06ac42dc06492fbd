"""OBJ texture coordinates and MTL maps: `vt` become corner uvs in glTF's convention (v flipped), a
material with a map becomes a Principled whose textures hold the images beside the .mtl (map_Pr
and map_Pm packed as G and B, map_d as the base colour's alpha), and a missing or corrupt image is
an error naming the .mtl, its line, the statement and the file."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from wgputrace import Diffuse, Glass, Principled, SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.testing.gltf_files import marked_pixels, png_bytes

QUAD = """mtllib maps.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
usemtl {material}
f 1/1 2/2 3/3 4/4
"""
GREY = np.full((2, 4, 1), 64, np.uint8)  # a single-channel map of another size than the colour map


def scene_with(tmp_path: Path, mtl: str, material: str = "textured"):
    (tmp_path / "colour.png").write_bytes(png_bytes(marked_pixels()))
    (tmp_path / "grey.png").write_bytes(png_bytes(GREY))
    (tmp_path / "maps.mtl").write_text(mtl)
    (tmp_path / "quad.obj").write_text(QUAD.format(material=material))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SceneLoadWarning)  # the parameters Principled lacks so far
        return load_scene(tmp_path / "quad.obj")


def test_map_kd_with_vt_flipped_to_gltf(tmp_path):
    (shape,) = scene_with(tmp_path, "newmtl textured\nKd 0.8 0.8 0.8\nmap_Kd -clamp on colour.png\n").shapes
    material = shape.material
    assert isinstance(material, Principled) and material.base_color == (1.0, 1.0, 1.0)  # the map replaces Kd
    texture = material.base_color_texture
    assert texture.srgb and (texture.wrap_s, texture.wrap_t) == ("clamp", "clamp")
    np.testing.assert_allclose(texture.linear_texels[0, 0], (1, 0, 0, 1))
    # vt (0, 0) is OBJ's bottom-left: glTF's (0, 1); the fan 1 2 3, 1 3 4
    np.testing.assert_array_equal(shape.uvs, [[[0, 1], [1, 1], [1, 0]], [[0, 1], [1, 0], [0, 0]]])


def test_roughness_and_metallic_maps_share_one_texture(tmp_path):
    mtl = "newmtl textured\nPm 0.5\nPr 0.25\nmap_Pr grey.png\nmap_Pm -imfchan r colour.png\n"
    material = scene_with(tmp_path, mtl).shapes[0].material
    assert (material.metallic, material.roughness) == (0.5, 0.25)
    texels = material.metallic_roughness_texture.linear_texels
    assert texels.shape == (2, 4, 4) and not material.metallic_roughness_texture.srgb
    np.testing.assert_allclose(texels[:, :, 1], 64 / 255)  # G: roughness
    np.testing.assert_allclose(texels[0, 0, 2], 1.0)  # B: metallic, the colour map's red, resampled
    np.testing.assert_allclose(texels[1, 3, 2], 128 / 255)


def test_map_d_is_the_base_colour_alpha(tmp_path):
    material = scene_with(tmp_path, "newmtl textured\nd 0.5\nmap_Kd colour.png\nmap_d grey.png\n").shapes[0].material
    assert material.alpha == 0.5
    texels = material.base_color_texture.linear_texels
    assert texels.shape == (4, 4, 4)
    np.testing.assert_allclose(texels[:, :, 3], 64 / 255)


def test_a_material_without_maps_keeps_its_mapping_and_no_uvs(tmp_path):
    (shape,) = scene_with(tmp_path, "newmtl textured\nKd 0.2 0.3 0.4\n").shapes
    assert isinstance(shape.material, Diffuse) and shape.uvs is None


def test_map_ks_alone_is_ignored_with_a_warning(tmp_path):
    (tmp_path / "maps.mtl").write_text("newmtl textured\nmap_Ks colour.png\n")
    (tmp_path / "quad.obj").write_text(QUAD.format(material="textured"))
    with pytest.warns(SceneLoadWarning, match=r"maps.mtl:2: map_Ks of 'textured' ignored"):
        assert isinstance(load_scene(tmp_path / "quad.obj").shapes[0].material, Diffuse)


def test_a_transparent_material_is_glass_its_maps_ignored(tmp_path):
    (tmp_path / "maps.mtl").write_text("newmtl textured\nd 0.5\nmap_Kd colour.png\n")
    (tmp_path / "quad.obj").write_text(QUAD.format(material="textured"))
    with pytest.warns(SceneLoadWarning, match=r"maps.mtl:1: 'textured' is transparent .* map_Kd ignored"):
        (shape,) = load_scene(tmp_path / "quad.obj").shapes
    assert isinstance(shape.material, Glass) and shape.uvs is None


@pytest.mark.parametrize(
    ("statement", "message"),
    [
        ("map_Kd missing.png", r"maps.mtl:2: map_Kd .*missing.png: cannot read the image"),
        ("map_Ke broken.png", r"maps.mtl:2: map_Ke .*broken.png: not a readable image"),
        ("bump", r"maps.mtl:2: bump names no image file"),
        ("norm -bm x colour.png", r"maps.mtl:2: norm .*colour.png: -bm must be a number, got 'x'"),
    ],
)
def test_bad_maps_are_errors_at_their_line(tmp_path, statement, message):
    (tmp_path / "broken.png").write_bytes(png_bytes(marked_pixels(16))[:60])
    with pytest.raises(SceneLoadError, match=message) as caught:
        scene_with(tmp_path, f"newmtl textured\n{statement}\n")
    assert "\n" not in str(caught.value)


def test_a_vt_reference_out_of_range_is_an_error(tmp_path):
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n")
    with pytest.raises(SceneLoadError, match=r"bad.obj:5: face texture coordinate index 2 is out of range"):
        load_scene(tmp_path / "bad.obj")
