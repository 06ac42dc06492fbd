"""The built-in scenes (wgputrace/scenes): each builds, and each has the property it exists for."""

from __future__ import annotations

import re

import numpy as np
import pytest

from wgputrace.scene import DegenerateTrianglesWarning, Emitter, Glossy
from wgputrace.scenes import BUILTIN_SCENES, DEFAULT_SCENE, default_scene, scene_by_name
from wgputrace.scenes.cornell import TINY_LIGHT_AREA_FRACTION
from wgputrace.scenes.glossy import ROUGHNESS_SWEEP

# float32 corners, compared after float64 arithmetic: a few roundings of relative size 2^-24
GEOMETRY_RTOL = 1e-6


def emitted_power(scene) -> float:
    """Sum of area x radiance (green) over emitting triangles; pi and both sides are common factors."""
    arrays = scene.arrays()
    v = arrays.vertices.astype(np.float64)
    area = 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
    radiance = np.array([m.radiance[1] if isinstance(m, Emitter) else 0.0 for m in arrays.materials], dtype=np.float64)
    return float(np.sum(area * radiance[arrays.material_index]))


@pytest.mark.parametrize("name", [name for name in BUILTIN_SCENES if name != "slivers"])
def test_every_scene_builds_without_degenerate_triangles(name):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", DegenerateTrianglesWarning)
        scene = scene_by_name(name)
        arrays = scene.arrays()
    assert np.isfinite(arrays.vertices).all() and len(arrays.vertices) > 0
    emits = any(m.emission_wgsl is not None for m in arrays.materials)
    assert emits or scene.environment is not None or scene.lights, f"{name} has no light"


def test_default_scene_is_the_cornell_box():
    assert DEFAULT_SCENE == "cornell"
    assert default_scene().triangle_count == 676


def test_unknown_scene_names_the_known_ones():
    # the whole list, sorted (not which scene sorts first: scenes come and go)
    known = ", ".join(sorted(BUILTIN_SCENES))
    with pytest.raises(ValueError, match=f"unknown scene 'nope'; built-in scenes: {re.escape(known)}$"):
        scene_by_name("nope")


def test_tiny_light_keeps_the_lamps_power_on_a_fraction_of_its_area():
    cornell, tiny = scene_by_name("cornell"), scene_by_name("tiny_light")
    np.testing.assert_allclose(emitted_power(tiny), emitted_power(cornell), rtol=GEOMETRY_RTOL)
    lamp = {s.name: s for s in cornell.shapes}["lamp"]
    small = {s.name: s for s in tiny.shapes}["lamp"]
    area = (
        np.ptp(lamp.vertices[..., 0]) * np.ptp(lamp.vertices[..., 2]),
        np.ptp(small.vertices[..., 0]) * np.ptp(small.vertices[..., 2]),
    )
    np.testing.assert_allclose(area[1] / area[0], TINY_LIGHT_AREA_FRACTION, rtol=1e-4)
    # same centre, and everything else untouched
    np.testing.assert_allclose(small.vertices.mean(axis=(0, 1)), lamp.vertices.mean(axis=(0, 1)), atol=1e-6)
    others = [s for s in cornell.shapes if s.name != "lamp"]
    for before, after in zip(others, [s for s in tiny.shapes if s.name != "lamp"], strict=True):
        np.testing.assert_array_equal(before.vertices, after.vertices)


@pytest.mark.parametrize("name, factor", [("cornell_1e-4", 1e-4), ("cornell_1e4", 1e4)])
def test_scaled_cornell_box_scales_geometry_and_camera(name, factor):
    cornell, scaled = scene_by_name("cornell"), scene_by_name(name)
    np.testing.assert_allclose(
        scaled.arrays().vertices, cornell.arrays().vertices.astype(np.float64) * factor, rtol=GEOMETRY_RTOL, atol=0
    )
    np.testing.assert_allclose(scaled.camera.position, np.multiply(cornell.camera.position, factor))
    assert scaled.camera.forward == cornell.camera.forward and scaled.camera.vfov_degrees == cornell.camera.vfov_degrees


def test_glossy_spheres_sweep_roughness_from_001_to_1():
    roughness = sorted(m.roughness for m in scene_by_name("glossy_spheres").materials if isinstance(m, Glossy))
    assert roughness == sorted(ROUGHNESS_SWEEP) and roughness[0] == 0.01 and roughness[-1] == 1.0


def test_slivers_drop_their_zero_area_triangles_and_keep_the_slivers():
    scene = scene_by_name("slivers")
    with pytest.warns(
        DegenerateTrianglesWarning,
        match="dropped 20 zero-area triangles; the first is triangle 300 of shape 'fan_wall'",
    ):
        arrays = scene.arrays()
    v = arrays.vertices.astype(np.float64)
    edges = np.linalg.norm(v[:, [1, 2, 0]] - v, axis=2)
    area = 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
    # a triangle's height over its longest edge: the slivers are thousands of times longer than wide
    thinness = 2.0 * area / edges.max(axis=1) ** 2
    assert np.all(area > 0) and thinness.min() < 1e-6 and np.median(thinness) < 1e-2


def test_axis_boxes_camera_and_faces_are_axis_aligned():
    scene = scene_by_name("axis_boxes")
    assert scene.camera.forward == (0.0, 0.0, 1.0)
    v = scene.arrays().vertices.astype(np.float64)
    normals = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    assert np.all(np.count_nonzero(normals, axis=1) == 1), "every face normal lies along one axis"


def test_night_street_has_a_thousand_lights_facing_the_street_or_down():
    """The many-light scene's windows face the street from both rows of facades, and its lamps
    face down: a window turned into its building would light the wall behind it only."""
    scene = scene_by_name("night_street")
    windows = np.concatenate([s.world_vertices for s in scene.shapes if s.name.startswith("windows_")]).astype(float)
    lamps = np.concatenate([s.world_vertices for s in scene.shapes if s.name.startswith("lamp_")]).astype(float)
    assert len(windows) // 2 >= 1000 and len(lamps) // 2 == 24

    def normals(triangles):
        n = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    towards_street = -np.sign(windows.mean(axis=1)[:, 0])
    np.testing.assert_allclose(normals(windows)[:, 0], towards_street)
    np.testing.assert_allclose(normals(lamps)[:, 1], -1.0)
