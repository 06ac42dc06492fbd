"""Paths that run out of llvmpipe's loop budget (65,535 iterations of all loops of an invocation
together) are dropped and counted, never accumulated half-traced; the flat list is refused where
its paths could run out; and an invocation taking several samples leaves a sample that runs out of
the budget it shares with the pixel's other samples to the next dispatch, so that paths that fit it
alone are never cut short."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Renderer, Shape, default_scene
from wgputrace.gpu.device import GpuContext

pytestmark = pytest.mark.gpu

SIZE = 16
SPP = 2
# Tiny triangles in two clusters outside the Cornell box, at opposite corners: the flat list's box
# for them spans the whole room, so it tests all of them for each of a path's rays (up to 18 at max
# depth 9); the BVH's boxes around each cluster keep rays from inside away from them.
HIDDEN_TRIANGLES = 6_000
# More than the budget: every ray from inside the room tests them all, so every path runs out of it
# at its first ray.
PAST_THE_BUDGET = 70_000
# Few enough that the flat list's longest path (2 x max depth 9 rays, each testing every triangle)
# fits the budget, many enough that eight average paths (5.4 rays) do not.
FITTING_ALONE = 2_000
SEVERAL = 8


def box_with_hidden_clutter(triangles: int = HIDDEN_TRIANGLES):
    scene = default_scene()
    rng = np.random.default_rng(7)
    low, high = scene.bounds()
    corner = np.where(np.arange(triangles)[:, None] % 2 == 0, low - 0.1, high + 0.1)
    corners = corner[:, None, :] + rng.uniform(-0.01, 0.01, (triangles, 3, 3))
    return scene.add(Shape("clutter", corners.astype(np.float32), Diffuse("grey")))


@pytest.mark.parametrize("samples_per_dispatch", [1, SEVERAL])
def test_paths_past_the_budget_are_dropped_and_counted(gpu_context, monkeypatch, samples_per_dispatch):
    if gpu_context.loop_iteration_limit is None:
        pytest.skip("this adapter has no loop budget (Mesa 22's llvmpipe has one, Mesa 25's none)")
    scene = box_with_hidden_clutter()
    with pytest.raises(Exception, match="ends shader loops after"):
        Renderer(scene, SIZE, SIZE, accel="flat")
    # Past the refusal (a limit no path reaches: the kernel still knows there is one), the shader's
    # own check must catch what the flat list's paths spend.
    monkeypatch.setattr(GpuContext, "loop_iteration_limit", property(lambda self: 10**9))
    flat = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=samples_per_dispatch)
    flat.render(SPP)
    assert flat.cut_short_samples > 0 and flat.nonfinite_samples == 0
    assert flat.dropped_samples == flat.cut_short_samples
    bvh = Renderer(scene, SIZE, SIZE, accel="bvh", samples_per_dispatch=samples_per_dispatch)
    bvh.render(SPP)
    assert bvh.cut_short_samples == 0 and bvh.dropped_samples == 0


@pytest.mark.parametrize("samples_per_dispatch", [1, 4])
def test_every_sample_cut_short_is_counted_once(gpu_context, monkeypatch, samples_per_dispatch):
    if gpu_context.loop_iteration_limit is None:
        pytest.skip("this adapter has no loop budget (Mesa 22's llvmpipe has one, Mesa 25's none)")
    monkeypatch.setattr(GpuContext, "loop_iteration_limit", property(lambda self: 10**9))
    scene = box_with_hidden_clutter(PAST_THE_BUDGET)
    renderer = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=samples_per_dispatch)
    renderer.render(SEVERAL - 1)
    assert renderer.cut_short_samples == renderer.dropped_samples == SIZE * SIZE * (SEVERAL - 1)
    assert not renderer.image().any()


@pytest.mark.parametrize("sampler", ["sobol", "independent"])
def test_samples_sharing_a_budget_are_left_to_the_next_dispatch_not_dropped(gpu_context, monkeypatch, sampler):
    if gpu_context.loop_iteration_limit is None:
        pytest.skip("this adapter has no loop budget (Mesa 22's llvmpipe has one, Mesa 25's none)")
    scene = box_with_hidden_clutter(FITTING_ALONE)
    alone = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=1, sampler=sampler)
    alone.render(SEVERAL + 3)
    together = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=SEVERAL, sampler=sampler)
    together.render(SEVERAL + 3)
    assert alone.dropped_samples == together.dropped_samples == 0
    np.testing.assert_array_equal(together.image(), alone.image())
    # what it avoids: the kernel without the shared budget in mind cuts samples short
    monkeypatch.setattr(GpuContext, "loop_iteration_limit", property(lambda self: None))
    unaware = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=SEVERAL, sampler=sampler)
    unaware.render(SEVERAL)
    assert not unaware.variant.loop_budget and unaware.cut_short_samples > 0
