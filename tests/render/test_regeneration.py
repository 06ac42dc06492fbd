"""Path regeneration: a dispatch that takes several samples of each pixel (`samples_per_dispatch`)
adds the same samples as one dispatch per sample, bit for bit: the same per-pixel sequences, the
same Kahan sums in the same order, the same guides and the same counts of dropped samples; the
last dispatch of a render takes what is left. Which count a renderer takes is the integrator's
choice per adapter type, one where the driver has a loop budget."""

from __future__ import annotations

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.gpu.device import GpuContext
from wgputrace.scenes import BUILTIN_SCENES

pytestmark = pytest.mark.gpu

SIZE = (24, 16)
SEED = 9
# one dispatch of REGENERATING samples and one of what is left
SPP = 11
REGENERATING = 8
# Scenes whose paths use every kind of draw: the Cornell box (emission, light sampling, glass,
# roulette), an environment (escaped light), stochastic alpha (its own stream per sample).
QUICK_SCENES = ("cornell", "env_sun_spheres", "alpha_blend")


def rendered(scene: str, samples_per_dispatch: int, **options) -> wt.Renderer:
    renderer = wt.Renderer(
        BUILTIN_SCENES[scene](), *SIZE, seed=SEED, samples_per_dispatch=samples_per_dispatch, **options
    )
    renderer.render(SPP)
    return renderer


def assert_same_samples(one: wt.Renderer, several: wt.Renderer) -> None:
    np.testing.assert_array_equal(several.image(), one.image())
    assert several.samples_per_pixel == one.samples_per_pixel == SPP
    assert (several.nonfinite_samples, several.cut_short_samples) == (one.nonfinite_samples, one.cut_short_samples)
    if one.guides_enabled:
        for name, guide in one.guides().items():
            np.testing.assert_array_equal(several.guides()[name], guide)


@pytest.mark.parametrize("sampler", ["sobol", "independent"])
@pytest.mark.parametrize("scene", QUICK_SCENES)
def test_several_samples_per_dispatch_are_the_same_samples(gpu_context, scene, sampler):
    one = rendered(scene, 1, sampler=sampler, guides=True)
    several = rendered(scene, REGENERATING, sampler=sampler, guides=True)
    assert several.samples_per_dispatch == REGENERATING and one.samples_per_dispatch == 1
    assert_same_samples(one, several)


@pytest.mark.slow
@pytest.mark.parametrize("integrator", ["mis", "nee", "bsdf"])
@pytest.mark.parametrize("scene", sorted(BUILTIN_SCENES))
def test_every_scene_renders_the_same_with_regeneration(gpu_context, scene, integrator):
    assert_same_samples(rendered(scene, 1, integrator=integrator), rendered(scene, 3, integrator=integrator))


def test_renders_continue_the_sequences_across_calls_and_restarts(gpu_context):
    one = wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, seed=SEED, samples_per_dispatch=1)
    several = wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, seed=SEED, samples_per_dispatch=REGENERATING)
    for renderer in (one, several):
        renderer.render(3)
        renderer.render(SPP - 3)  # 3 + 8: two renders, each with a dispatch of fewer samples
    assert_same_samples(one, several)
    several.restart()
    several.render(SPP)
    np.testing.assert_array_equal(several.image(), one.image())


def test_the_integrator_chooses_the_count_for_the_adapter(gpu_context, monkeypatch):
    adapter_type = gpu_context.adapter.info["adapter_type"]
    mis = wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE)
    assert mis.samples_per_dispatch == mis.integrator.samples_per_dispatch(adapter_type)
    assert wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, integrator="bdpt").samples_per_dispatch == 1
    # under a loop budget too, the kernel then leaving samples that run out of it to the next dispatch
    for limit in (None, 65_535):
        monkeypatch.setattr(GpuContext, "loop_iteration_limit", property(lambda self, limit=limit: limit))
        several = wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, samples_per_dispatch=REGENERATING)
        assert several.variant.loop_budget == (limit is not None)
        assert not wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, samples_per_dispatch=1).variant.loop_budget


def test_an_integrator_without_regeneration_refuses_several(gpu_context):
    with pytest.raises(ValueError, match="bdpt integrator's kernel takes one sample"):
        wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, integrator="bdpt", samples_per_dispatch=2)
    with pytest.raises(ValueError, match="samples_per_dispatch must be at least 1"):
        wt.Renderer(BUILTIN_SCENES["cornell"](), *SIZE, samples_per_dispatch=0)
