"""The two-level structure's records on the host (no GPU): where each part sits in the arrays the
GPU gets, what a transform edit changes (the top level only), and the limits named."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Scene, make_box, make_icosphere, make_plane, model_matrix
from wgputrace.bvh.wide import WIDE_COUNT_BITS, WIDE_EMPTY, WIDE_LEAF
from wgputrace.render import instance_records
from wgputrace.render.instance_records import outward_float32, shifted_references
from wgputrace.render.scene_mirror import INSTANCES, NODES, TRIANGLES, SceneMirror
from wgputrace.scene import SceneError


def field(count: int = 6) -> Scene:
    ground = make_plane((0, -1, 0), (0, 0, 0), (10, 10), Diffuse("ground", (0.5, 0.5, 0.5)), "ground")
    ball = make_icosphere((0, 0, 0), (0, 0, 0), 0.5, 2, Diffuse("ball", (0.8, 0.2, 0.2)), "ball", smooth=True)
    crate = make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("crate", (0.2, 0.8, 0.2)), "crate")
    scene = Scene([ground])
    for k in range(count):
        scene.add_instance((ball, crate)[k % 2], model_matrix((1.5 * k - 4, 0, 0), (0, 0.3 * k, 0), 1.0))
    return scene


def test_the_arrays_hold_the_top_level_then_the_world_then_each_mesh_once():
    mirror = SceneMirror(field(), "bvh")
    instancing, arrays = mirror.instancing, mirror.arrays
    assert len(arrays[TRIANGLES]) == 2 + 320 + 12  # the ground, then one ball and one crate
    nodes = arrays[NODES]
    assert len(nodes) == instancing.top_records + len(mirror.nodes) + len(instancing.mesh_nodes)
    children = nodes["children"]
    leaves = children[(children & WIDE_LEAF != 0) & (children != WIDE_EMPTY)]
    first = (leaves & ~np.uint32(WIDE_LEAF)) >> WIDE_COUNT_BITS
    assert first.max() < len(arrays[TRIANGLES])
    interior = children[children & WIDE_LEAF == 0]
    assert interior.max() < len(nodes)
    records = arrays[INSTANCES]
    # the world is slot 0; an instance's slot s names its record, s - 1, in the hit words
    slots = records["slot"].astype(np.int64)
    assert np.count_nonzero(slots == 0) == 1
    np.testing.assert_array_equal(slots[slots > 0], np.flatnonzero(slots > 0) + 1)
    world = records[records["slot"] == 0][0]
    assert world["root"] == instancing.top_records
    # mesh triangles in object space, their material the mesh's
    assert set(arrays[TRIANGLES]["material"][2:]) == {1, 2}


def test_moving_an_instance_changes_only_top_level_records_and_its_own():
    scene = field()
    mirror = SceneMirror(scene, "bvh")
    top_records, rebuilds = mirror.instancing.top_records, mirror.rebuilds
    before = mirror.arrays[NODES].copy()
    scene.instances[2].transform = model_matrix((0, 2, 0), (0, 0, 0), 1.2)
    changes = mirror.update()
    assert set(changes) == {NODES, INSTANCES}
    assert changes[NODES].max() < top_records and len(changes[INSTANCES]) == 1
    assert mirror.rebuilds == rebuilds
    np.testing.assert_array_equal(mirror.arrays[NODES][top_records:], before[top_records:])
    moved = mirror.arrays[INSTANCES][changes[INSTANCES][0]]
    np.testing.assert_allclose(moved["object_to_world1"], [0, 1.2, 0, 2])
    assert mirror.update() == {}  # nothing more to do


def test_adding_an_instance_rebuilds():
    scene = field()
    mirror = SceneMirror(scene, "bvh")
    rebuilds = mirror.rebuilds
    scene.add_instance(scene.instances[0].mesh, np.eye(4))
    changes = mirror.update()
    assert mirror.rebuilds == rebuilds + 1 and len(changes[INSTANCES]) == len(scene.instances) + 1


def test_instances_need_the_bvh_a_shape_and_a_word_that_addresses_them(monkeypatch):
    with pytest.raises(SceneError, match="instances need the 'bvh' acceleration"):
        SceneMirror(field(), "flat")
    alone = field()
    alone.shapes = []
    with pytest.raises(SceneError, match="6 instances and no Shape: add at least one Shape"):
        SceneMirror(alone, "bvh")
    monkeypatch.setattr(instance_records, "WORD_BITS", 10)  # 3 bits of slot, 7 of triangle
    with pytest.raises(SceneError, match=r"6 instances and 334 stored triangles do not fit a 10-bit hit word"):
        SceneMirror(field(), "bvh")


def test_references_move_and_boxes_round_outward():
    refs = np.array([5, WIDE_LEAF | (3 << WIDE_COUNT_BITS) | 2, WIDE_EMPTY], np.uint32)
    np.testing.assert_array_equal(
        shifted_references(refs, 100, 1000), [105, WIDE_LEAF | (1003 << WIDE_COUNT_BITS) | 2, WIDE_EMPTY]
    )
    low, high = outward_float32(np.array([0.1]), np.array([0.1]))
    assert low[0] <= 0.1 <= high[0] and low[0] < high[0]
