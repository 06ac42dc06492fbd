"""Paths that run out of llvmpipe's loop budget (65,535 iterations of all loops of an invocation
together) are dropped and counted, never accumulated half-traced; the flat list is refused where
its paths could run out; and where there is a budget a renderer takes one sample per dispatch, so
that paths that fit it alone are never cut short for sharing it with the pixel's other samples."""

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
    # Past the refusal, the shader's own check must catch what the flat list's paths spend.
    monkeypatch.setattr(GpuContext, "loop_iteration_limit", property(lambda self: None))
    flat = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=samples_per_dispatch)
    flat.render(SPP)
    assert flat.cut_short_samples > 0 and flat.nonfinite_samples == 0
    assert flat.dropped_samples == flat.cut_short_samples
    bvh = Renderer(scene, SIZE, SIZE, accel="bvh", samples_per_dispatch=samples_per_dispatch)
    bvh.render(SPP)
    assert bvh.cut_short_samples == 0 and bvh.dropped_samples == 0


def test_a_budget_keeps_one_sample_per_dispatch(gpu_context):
    if gpu_context.loop_iteration_limit is None:
        pytest.skip("this adapter has no loop budget (Mesa 22's llvmpipe has one, Mesa 25's none)")
    scene = box_with_hidden_clutter(FITTING_ALONE)
    alone = Renderer(scene, SIZE, SIZE, accel="flat")
    alone.render(SEVERAL)
    assert alone.samples_per_dispatch == 1 and alone.dropped_samples == 0
    # what it avoids: the same paths taken several to an invocation run past the budget together
    together = Renderer(scene, SIZE, SIZE, accel="flat", samples_per_dispatch=SEVERAL)
    together.render(SEVERAL)
    assert together.cut_short_samples > 0
