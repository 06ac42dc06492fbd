"""The BVH traversal's stack is compiled as large as the scene's tree needs (rounded up to
STACK_SIZE_STEP), and grows, with a new pipeline, when an edit makes the tree need more."""

from __future__ import annotations

import pytest

from wgputrace import Diffuse, Renderer, Shape, default_scene
from wgputrace.kernels.traversal import BVH_STACK_SIZE, STACK_SIZE_STEP, traversal_stack_size
from wgputrace.testing.scenes import geometric_peel_scene

SIZE = 16


@pytest.mark.parametrize(
    ("needed", "compiled"), [(0, 16), (16, 16), (17, 32), (34, 48), (102, 112), (BVH_STACK_SIZE, BVH_STACK_SIZE)]
)
def test_stack_size_rounds_the_need_up_to_the_step_within_the_largest(needed, compiled):
    assert STACK_SIZE_STEP == 16 and BVH_STACK_SIZE % STACK_SIZE_STEP != 0  # the last size is capped
    assert traversal_stack_size(needed) == compiled


def test_a_need_past_the_largest_stack_is_refused():
    with pytest.raises(ValueError, match=f"exceeds BVH_STACK_SIZE = {BVH_STACK_SIZE}"):
        traversal_stack_size(BVH_STACK_SIZE + 1)


@pytest.mark.gpu
def test_the_stack_follows_the_tree_through_an_edit(gpu_context):
    scene = default_scene()
    renderer = Renderer(scene, SIZE, SIZE)
    assert renderer.records.wide.max_stack <= STACK_SIZE_STEP
    assert renderer.variant.scene.stack_size == STACK_SIZE_STEP
    first_kernel = renderer.kernel
    # tiny triangles peeled off a few per level: a tree whose 4-wide traversal needs 102 entries,
    # more than a stack sized for the builder's depth limit alone (96) would hold
    scene.add(Shape("peel", geometric_peel_scene(), Diffuse("grey")))
    renderer.render(1)
    needed = renderer.records.wide.max_stack
    assert needed > STACK_SIZE_STEP
    assert renderer.variant.scene.stack_size == traversal_stack_size(needed)
    assert renderer.kernel is not first_kernel
    assert renderer.dropped_samples == 0
