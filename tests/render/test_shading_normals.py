"""Smooth shading from per-vertex normals: a coarse sphere with its sphere normals shades without
facet steps and as bright as a finely subdivided flat sphere; normals that contradict the geometry
give no NaN; flat scenes bind and compile none of it; edits of a smooth shape reach the GPU as
counted uploads, the picture after them that of a fresh renderer."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from wgputrace import Environment
from wgputrace.gpu.layout import TRIANGLE_VERTICES, VERTEX_NORMAL
from wgputrace.kernels.bind_groups import SHADING_GROUP
from wgputrace.kernels.shading_normals import shading_normals_hook
from wgputrace.kernels.variant import KernelVariant, SceneFeatures
from wgputrace.render.renderer import Renderer
from wgputrace.render.scene_mirror import VERTEX_INDICES, VERTEX_NORMALS
from wgputrace.scene import Camera, Diffuse, DirectionalLight, Scene, Shape
from wgputrace.scene.shapes import make_icosphere, model_matrix

pytestmark = pytest.mark.gpu

SIZE = 48
SPP = 64
SEED = 3
GREY = Diffuse("ball", color=(0.8, 0.8, 0.8))
# the pixels that see the sphere's front, well inside its silhouette
CENTRE = slice(14, 34)


def sphere_scene(iterations: int, smooth: bool, light_direction=(0.0, 0.0, 1.0)) -> Scene:
    """A unit sphere seen head-on from 3 units, lit by a directional light (no 1/r^2: the coarse
    sphere's facets lie inside the fine one's surface, nearer or farther than it)."""
    ball = make_icosphere((0, 0, 0), (0.3, 0.2, 0.1), 1.0, iterations, GREY, "ball", smooth=smooth)
    scene = Scene([ball], Camera.looking_at((0, 0, -3.0), (0, 0, 0), vfov_degrees=45.0))
    scene.add_light(DirectionalLight(direction=light_direction, irradiance=3.0))
    return scene


@cache
def sphere_image(iterations: int, smooth: bool) -> np.ndarray:
    renderer = Renderer(sphere_scene(iterations, smooth), SIZE, SIZE, seed=SEED, max_depth=2)
    renderer.render(SPP)
    return renderer.image()[CENTRE, CENTRE, 0]


def largest_step(image: np.ndarray) -> float:
    """The largest difference of horizontally neighbouring pixels."""
    return float(np.abs(np.diff(image, axis=1)).max())


def test_a_coarse_smooth_sphere_shows_no_facet_steps():
    # measured: flat 80 triangles 0.125, smooth 0.025, flat 20,480 triangles 0.013 (pixel jitter)
    assert largest_step(sphere_image(1, smooth=False)) > 0.08  # the facets this test must see go
    assert largest_step(sphere_image(1, smooth=True)) < 0.04


def test_a_coarse_smooth_sphere_is_as_bright_as_a_fine_flat_one():
    # head-on light: the terminator (and its shadowing term) is outside the compared pixels;
    # measured 0.724 against 0.7305
    smooth, fine = sphere_image(1, smooth=True).mean(), sphere_image(5, smooth=False).mean()
    assert abs(smooth - fine) < 0.02 * fine


def test_normals_against_the_geometry_give_no_nan():
    """Corner normals below the surface, nearly in its plane, or cancelling where interpolated,
    seen at grazing angles under an environment and a low light: finite, non-negative pixels."""
    triangle = np.array([[[-1, 0, -1], [1, 0, -1], [0, 0, 1]]], np.float32)  # faces -y
    cases = {
        "below": [[[0, 1, 0], [0.2, 1, 0], [0, 1, 0.2]]],
        "grazing": [[[1, -1e-4, 0], [0, -1e-4, 1], [-1, -1e-4, 0]]],
        "cancelling": [[[0, -1, 0], [0, 1, 0], [0, -1, 0.01]]],
    }
    shapes = [
        Shape(name, triangle + np.float32([3 * index - 3, 0, 0]), GREY, normals=normals)
        for index, (name, normals) in enumerate(cases.items())
    ]
    scene = Scene(shapes, Camera.looking_at((0, -0.05, -6.0), (0, 0, 0), vfov_degrees=50.0))
    scene.environment = Environment(radiance=(1.0, 1.0, 1.0))
    scene.add_light(DirectionalLight(direction=(0.3, 0.05, 1.0), irradiance=2.0))
    renderer = Renderer(scene, 32, 32, seed=SEED)
    renderer.render(16)
    image = renderer.image()
    assert renderer.nonfinite_samples == 0  # the image drops them: count them
    assert np.isfinite(image).all() and (image >= 0).all()
    assert image.max() > 0  # the triangles are seen lit, not dropped


def test_flat_scenes_bind_and_compile_none_of_it():
    flat_hook, smooth_hook = (shading_normals_hook(KernelVariant(SceneFeatures(smooth=on))) for on in (False, True))
    for included in (SHADING_GROUP.file, "shading/smooth_normals.wgsl"):
        assert included not in flat_hook and included in smooth_hook
    flat = Renderer(sphere_scene(1, smooth=False), 8, 8)
    smooth = Renderer(sphere_scene(1, smooth=True), 8, 8)
    assert not flat.smooth_shading and "shading" not in flat.bind_groups
    assert VERTEX_NORMALS not in flat.gpu_scene_bytes and VERTEX_INDICES not in flat.gpu_scene_bytes
    assert smooth.smooth_shading and "shading" in smooth.bind_groups
    # the 80 triangles of the once-subdivided icosahedron share its 42 vertices
    assert smooth.gpu_scene_bytes[VERTEX_INDICES] == 80 * TRIANGLE_VERTICES.size
    assert smooth.gpu_scene_bytes[VERTEX_NORMALS] == 42 * VERTEX_NORMAL.size
    assert flat.kernel is not smooth.kernel


def test_edits_of_a_smooth_shape_are_counted_uploads_and_match_a_fresh_renderer():
    scene = sphere_scene(1, smooth=True, light_direction=(-1.0, -0.3, 0.4))
    renderer = Renderer(scene, 24, 24, seed=SEED)
    renderer.render(2)
    ball = scene.shapes[0]
    ball.transform = model_matrix((0.1, 0.0, 0.2), (0.0, 0.7, 0.0), 1.0)
    uploads = renderer.update()
    # a move keeps which corners share a vertex: the normals change, the triangles' vertices do not
    assert 0 < uploads[VERTEX_NORMALS].bytes <= 42 * VERTEX_NORMAL.size and VERTEX_INDICES not in uploads
    renderer.render(2)
    fresh = Renderer(scene, 24, 24, seed=SEED)
    fresh.render(2)
    np.testing.assert_array_equal(renderer.image(), fresh.image())
    # losing the normals: the flat kernel and no vertex normals, as a fresh renderer of the flat sphere
    ball.normals = None
    renderer.update()
    assert not renderer.smooth_shading and "shading" not in renderer.bind_groups
    renderer.render(2)
    fresh = Renderer(scene, 24, 24, seed=SEED)
    fresh.render(2)
    np.testing.assert_array_equal(renderer.image(), fresh.image())
