"""Vertex colours in the Mitsuba export (`mitsuba_scene.vertex_colored`): the material's colour
parameter reads the mesh's `vertex_color` attribute, which holds the corner colours times the
material's colour; what cannot be exported says so. Needs no Mitsuba: the dicts and arrays are ours
(the `vertex_colored_triangles` reference renders them)."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.reference.mitsuba_scene import VERTEX_COLOR_ATTRIBUTE, bsdf_dict, vertex_colored
from wgputrace.scene import Diffuse, Emitter, Glossy, Principled

READ_FROM_VERTICES = {"type": "mesh_attribute", "name": VERTEX_COLOR_ATTRIBUTE}


def corner_colors(rng: np.random.Generator, triangles: int = 3) -> np.ndarray:
    colors = rng.uniform(0.0, 1.0, (triangles, 3, 4)).astype(np.float32)
    colors[..., 3] = 1.0
    return colors


@pytest.mark.parametrize(
    "material, parameter",
    [
        (Diffuse("d", color=(0.9, 0.5, 0.25)), "reflectance"),
        (Glossy("g", color=(0.5, 0.75, 1.0)), "specular_reflectance"),
    ],
)
def test_the_colour_parameter_reads_the_corner_colours_times_the_materials(material, parameter):
    colors = corner_colors(np.random.default_rng(25))
    values = vertex_colored(material, colors)
    np.testing.assert_allclose(values, colors[..., :3] * np.asarray(material.mitsuba_bsdf()[parameter]["value"]))
    bsdf = bsdf_dict(material, colored=True)
    assert bsdf["type"] == "twosided" and bsdf["bsdf"][parameter] == READ_FROM_VERTICES
    assert {key: value for key, value in bsdf["bsdf"].items() if key != parameter} == {
        key: value for key, value in material.mitsuba_bsdf().items() if key != parameter
    }


def test_white_vertices_and_emitters_keep_their_plain_export():
    colors = corner_colors(np.random.default_rng(26))
    assert vertex_colored(Diffuse("d"), np.ones_like(colors)) is None
    assert vertex_colored(Emitter("lamp", color=(1.0, 1.0, 1.0), emittance=5.0), colors) is None


def test_a_material_whose_colour_no_parameter_carries_is_refused_by_name():
    colors = corner_colors(np.random.default_rng(27))
    with pytest.raises(ValueError, match="material 'p': vertex colours on a Principled have no Mitsuba 3 export"):
        vertex_colored(Principled("p"), colors)
