"""Absorption inside materials on the GPU (`volume`): through an index-matched glass block (ior 1:
no Fresnel, no refraction) seen head-on by an orthographic camera against a constant sky, every
camera ray crosses the block's depth d exactly, so every pixel is sky x attenuation_color^(d /
attenuation_distance) with no noise. A channel that absorbs everything gives 0, never NaN; editing
a material to absorb compiles absorption in; bdpt refuses the material by name."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Renderer, save_image
from wgputrace.scene import Glass, OrthographicCamera, Scene, make_box
from wgputrace.scene.lights.environment import Environment

pytestmark = pytest.mark.gpu

SIZE = 8
SPP = 4
SKY = np.array([0.8, 0.9, 1.1])
DEPTH = 2.0  # the block's extent along the view; its other sides are wider than the view
# camera -> front face -> back face -> the sky
MAX_DEPTH = 4
# float32 along the path and lavapipe's exp (a few ulp of |sigma_a x d| ~ 3)
EXP_RTOL = 1e-4
ESTIMATORS = ("mis", "nee", "bsdf")


def block_scene(material: Glass) -> Scene:
    block = make_box((0.0, 0.0, 0.0), (0, 0, 0), (4.0, 4.0, DEPTH), material, "block")
    camera = OrthographicCamera.looking_at((0.0, 0.0, -5.0), (0.0, 0.0, 0.0), view_height=1.0)
    scene = Scene([block], camera)
    scene.environment = Environment(radiance=tuple(SKY))
    return scene


def rendered(renderer: Renderer, failure_path) -> np.ndarray:
    renderer.render(SPP)
    image = renderer.image()
    save_image(failure_path, image)
    assert renderer.nonfinite_samples == 0
    return image


@pytest.mark.parametrize("integrator", ESTIMATORS)
def test_an_index_matched_block_transmits_sky_times_color_to_the_depth_over_distance(
    gpu_context, failure_dir, integrator
):
    color, distance = np.array([0.5, 0.8, 0.25]), 1.5
    glass = Glass("tinted", ior=1.0, attenuation_color=tuple(color), attenuation_distance=distance)
    renderer = Renderer(block_scene(glass), SIZE, SIZE, seed=3, max_depth=MAX_DEPTH, integrator=integrator)
    assert "absorbing" in renderer.variant.label
    image = rendered(renderer, failure_dir / f"absorbing_block_{integrator}.exr")
    expected = SKY * color ** (DEPTH / distance)
    np.testing.assert_allclose(image, np.broadcast_to(expected, image.shape), rtol=EXP_RTOL)


def test_a_channel_of_color_zero_is_black_not_nan(gpu_context, failure_dir):
    glass = Glass("red_opaque", ior=1.0, attenuation_color=(0.0, 0.5, 1.0), attenuation_distance=1.0)
    image = rendered(Renderer(block_scene(glass), SIZE, SIZE, max_depth=MAX_DEPTH), failure_dir / "zero_channel.exr")
    assert np.all(image[..., 0] == 0.0)
    np.testing.assert_allclose(
        image[..., 1:], np.broadcast_to(SKY[1:] * [0.25, 1.0], image[..., 1:].shape), rtol=EXP_RTOL
    )


def test_editing_a_glass_to_absorb_compiles_absorption_in(gpu_context, failure_dir):
    glass = Glass("clear", ior=1.0)
    renderer = Renderer(block_scene(glass), SIZE, SIZE, max_depth=MAX_DEPTH)
    assert "absorbing" not in renderer.variant.label  # nothing to absorb: the kernel reads no absorption
    np.testing.assert_allclose(rendered(renderer, failure_dir / "clear.exr"), np.broadcast_to(SKY, (SIZE, SIZE, 3)))
    glass.attenuation_distance = 1.0
    glass.attenuation_color = (0.5, 0.5, 0.5)
    renderer.update()
    assert "absorbing" in renderer.variant.label
    image = rendered(renderer, failure_dir / "edited.exr")
    np.testing.assert_allclose(image, np.broadcast_to(SKY * 0.25, image.shape), rtol=EXP_RTOL)


def test_bdpt_refuses_an_absorbing_material_by_name(gpu_context):
    glass = Glass("amber", attenuation_color=(0.9, 0.6, 0.3), attenuation_distance=1.0)
    with pytest.raises(ValueError, match=r"^material 'amber' absorbs the light inside it .* bdpt integrator") as caught:
        Renderer(block_scene(glass), SIZE, SIZE, integrator="bdpt")
    assert "\n" not in str(caught.value)
    clear = Glass("clear")
    renderer = Renderer(block_scene(clear), SIZE, SIZE, integrator="bdpt")
    clear.attenuation_distance = 2.0  # white still: nothing absorbed yet
    renderer.update()
    clear.attenuation_color = (0.5, 0.5, 0.5)
    with pytest.raises(ValueError, match=r"^material 'clear' absorbs .* use 'bsdf', 'nee', 'mis'"):
        renderer.update()
