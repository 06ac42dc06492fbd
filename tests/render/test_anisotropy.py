"""Principled's anisotropy rendered (`anisotropic`, `anisotropy_rotation`, WGSL `surface_frame`): an
anisotropic metal quad seen head-on under a light from the camera's side. Its highlight stretches
along the tangent (u, +x here) and turning the anisotropy by 90 degrees stretches it across; a quad
without texture coordinates takes Mitsuba's fallback tangent (coordinate_system of its normal, +x
for this quad) and renders as the one with them; bdpt renders what the path tracer does; an edit
that turns anisotropy on renders as a scene made with it (tangents uploaded, the kernel recompiled)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace import DirectionalLight
from wgputrace.render.renderer import Renderer
from wgputrace.scene import Camera, Principled, Scene, Shape
from wgputrace.testing.scenes import uv_square

pytestmark = pytest.mark.gpu

SIZE = 32
SPP = 16
# a quad in z = 0 facing the camera at z = -3 (normal -z); u along +x
QUAD, QUAD_UVS = uv_square(normal_z=-1)
CAMERA = Camera.looking_at((0, 0, -3), (0, 0, 0), vfov_degrees=40.0)
# a highlight's spread along one image axis is more than this many times the other's
STRETCH = 3.0


def scene_of(rotation: float = 0.0, uvs: bool = True) -> Scene:
    metal = Principled(
        "brushed", (0.9, 0.9, 0.9), metallic=1.0, roughness=0.3, anisotropic=1.0, anisotropy_rotation=rotation
    )
    scene = Scene([Shape("quad", QUAD, metal, uvs=QUAD_UVS if uvs else None)], CAMERA)
    scene.add_light(DirectionalLight((0.0, 0.0, 1.0), 3.0))
    return scene


def render(scene: Scene, **options) -> np.ndarray:
    renderer = Renderer(scene, SIZE, SIZE, seed=5, max_depth=2, **options)
    renderer.render(SPP)
    return renderer.image().mean(axis=-1)


def spreads(image: np.ndarray) -> tuple[float, float]:
    """The brightness-weighted standard deviations of the column and of the row (pixels)."""
    rows, columns = np.indices(image.shape)
    weights = image / image.sum()
    spread = [math.sqrt((weights * (c - (weights * c).sum()) ** 2).sum()) for c in (columns, rows)]
    return spread[0], spread[1]


def test_the_highlight_stretches_along_the_tangent_and_turns_with_the_rotation():
    along = render(scene_of())
    across = render(scene_of(rotation=math.pi / 2))
    assert along.max() > 0.1
    x, y = spreads(along)
    assert x > STRETCH * y, f"the highlight spreads {x:.2f} px along the tangent (image x), {y:.2f} across"
    x, y = spreads(across)
    assert y > STRETCH * x, f"turned 90 degrees the highlight spreads {x:.2f} px along x, {y:.2f} along y"


def test_the_rotation_turns_the_tangent_towards_gltfs_bitangent():
    """glTF measures anisotropyRotation from the tangent (u: +x) towards the bitangent (up the
    texture image, v decreasing: +y), so +45 degrees stretches the highlight along world (1, 1, 0):
    up and to the left in the image of a camera looking along +z (its right is -x), the diagonal
    whose columns and rows grow together; -45 degrees along the other diagonal."""
    for rotation, sign in ((math.pi / 4, 1.0), (-math.pi / 4, -1.0)):
        image = render(scene_of(rotation=rotation))
        rows, columns = np.indices(image.shape)
        weights = image / image.sum()
        covariance = (weights * (columns - (weights * columns).sum()) * (rows - (weights * rows).sum())).sum()
        x, y = spreads(image)
        assert sign * covariance > 0.5 * x * y, (
            f"turned {rotation:.3f}: covariance {covariance:.2f}, spreads {x:.2f} {y:.2f}"
        )


def test_without_texture_coordinates_the_tangent_is_mitsubas_fallback():
    np.testing.assert_allclose(render(scene_of(uvs=False)), render(scene_of()), rtol=1e-4, atol=1e-6)


def test_bdpt_turns_the_frame_as_the_path_tracer():
    traced = render(scene_of(rotation=math.pi / 2), integrator="bdpt")
    x, y = spreads(traced)
    assert y > STRETCH * x


def test_an_edit_that_turns_anisotropy_on_renders_as_a_scene_made_with_it():
    scene = scene_of()
    scene.materials[0].anisotropic = 0.0
    renderer = Renderer(scene, SIZE, SIZE, seed=5, max_depth=2)
    renderer.render(SPP)
    scene.materials[0].anisotropic = 1.0
    renderer.restart()
    renderer.render(SPP)
    np.testing.assert_allclose(renderer.image().mean(axis=-1), render(scene_of()), rtol=1e-4, atol=1e-6)
