"""The bidirectional kernel's MIS weights sum to one over the strategies that can sample a path,
checked on the GPU for the paths it samples (override BDPT_CHECK_WEIGHT_SUMS, WGSL
`check_weight_sums`): every light kind (triangles, textured emission, point, spot,
directional, sun, environment) and material (diffuse, glossy, glass, principled, textures) in the
scenes below. A strategy whose density another weight sees differently (a stand-in used on one
side only, a shading normal chosen differently from the light's end) breaks the sum."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Renderer
from wgputrace.scenes import scene_by_name

pytestmark = pytest.mark.gpu

SIZE = 24
SEED = 18
MAX_DEPTH = 8
# f32 weights of up to MAX_DEPTH + 1 strategies, each from density ratios squared
TOLERANCE = 1e-4
# the scenes, and how many strategies at least can sample their checked paths on average: every
# path through the glass to the emitting walls is found by hitting them alone (glass vertices
# connect to nothing), the rest by several
SCENES = {
    "cornell": 2.0,
    "glossy_spheres": 2.0,
    "glass_grazing": 1.0,
    "env_sun_spheres": 2.0,
    "point_spot_directional": 2.0,
    "principled_spheres": 2.0,
}


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_weights_sum_to_one_for_sampled_paths(gpu_context, scene):
    renderer = Renderer(
        scene_by_name(scene),
        SIZE,
        SIZE,
        seed=SEED,
        max_depth=MAX_DEPTH,
        integrator="bdpt",
        shader_overrides={"BDPT_CHECK_WEIGHT_SUMS": True},
    )
    renderer.render(1)
    deviation, paths, strategies = np.moveaxis(renderer.image(), -1, 0)
    assert renderer.nonfinite_samples == 0
    worst = np.unravel_index(np.argmax(deviation), deviation.shape)
    assert deviation.max() < TOLERANCE, f"{scene}: weights sum to 1 +- {deviation.max():.3g} at pixel {worst}"
    # the check saw paths, and as many strategies to weigh as the scene offers
    assert paths.sum() > SIZE * SIZE / 4
    assert strategies.sum() >= SCENES[scene] * paths.sum()
