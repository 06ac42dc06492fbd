"""Editing a rendered scene: each kind of edit uploads only what it touches (counted per buffer),
accumulation restarts only when the picture can change, and the picture after the edit is, bit for
bit, what a fresh Renderer of the edited scene makes with the same seed (a restart puts every
pixel's random sequence back at the seed; lights and BVH order cannot leak into the image)."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Glass, Renderer, Scene, default_scene, make_box, make_icosphere
from wgputrace import model_matrix as place
from wgputrace.bvh.wide import EMPTY_SLOT
from wgputrace.gpu.device import DeviceLimitError
from wgputrace.gpu.layout import FRAME, MATERIAL, TRIANGLE, WIDE_BVH_NODE
from wgputrace.gpu.texels import TEXEL_BYTES
from wgputrace.gpu.tracked_buffer import SPARE_FRACTION, UploadCount
from wgputrace.render import scene_mirror, scene_records
from wgputrace.scene import SceneError
from wgputrace.testing.harness import read_binding
from wgputrace.testing.oracles import bvh_bounds_from_scratch

SIZE = 24
SEED = 5
SPP = 2


def triangle_corners(records: np.ndarray) -> np.ndarray:
    return np.stack([records["v0"], records["v1"], records["v2"]], axis=1)


def fresh_image(scene: Scene) -> np.ndarray:
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED)
    renderer.render(SPP)
    return renderer.image()


def rendered(renderer: Renderer) -> np.ndarray:
    renderer.render(SPP)
    assert renderer.samples_per_pixel == SPP, "the edit should have restarted accumulation"
    return renderer.image()


@pytest.fixture
def cornell(gpu_context):
    scene = default_scene()
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED)
    renderer.render(SPP)
    return scene, renderer


def material(scene: Scene, name: str):
    return next(m for m in scene.materials if m.name == name)


def test_an_unchanged_scene_uploads_nothing_and_keeps_accumulating(cornell):
    _, renderer = cornell
    renderer.render(SPP)
    assert renderer.upload_stats == {}
    assert renderer.samples_per_pixel == 2 * SPP


def test_a_material_colour_edit_uploads_one_material_record(cornell):
    scene, renderer = cornell
    material(scene, "red").color = (0.2, 0.6, 0.9)
    image = rendered(renderer)
    assert renderer.upload_stats == {"materials": UploadCount(bytes=MATERIAL.size, calls=1)}
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_a_camera_move_uploads_only_the_frame(cornell):
    scene, renderer = cornell
    scene.camera = Camera((0.1, 0.35, -1.1), (-0.1, 0, 1), (0, 1, 0), 50.0)
    image = rendered(renderer)
    assert renderer.upload_stats == {"frame": UploadCount(bytes=FRAME.size, calls=1)}
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_moving_one_mesh_uploads_its_triangles_and_the_nodes_above_them(cornell, monkeypatch):
    scene, renderer = cornell
    sphere = scene.shape("sphere2")
    nodes_before = renderer.records.nodes.copy()
    sphere.transform = place((0.0, -0.05, -0.1), (0, 0, 0), 1.0)
    # a refit keeps the topology: the wide records' boxes are regathered, the tree not collapsed again
    monkeypatch.setattr(scene_records, "collapse", lambda bvh: pytest.fail("a refit collapsed the tree again"))
    image = rendered(renderer)
    stats = renderer.upload_stats
    assert set(stats) == {"triangles", "bvh nodes"}
    assert stats["triangles"].bytes == sphere.triangle_count * TRIANGLE.size
    changed_nodes = np.count_nonzero(renderer.records.nodes != nodes_before)
    # the GPU's 4-wide records (WIDE_BVH_NODE, 112 B), only those whose boxes changed
    assert stats["bvh nodes"].bytes == changed_nodes * WIDE_BVH_NODE.size
    assert changed_nodes < len(nodes_before) // 2  # not the whole tree
    assert stats["triangles"].calls <= sphere.triangle_count // 8  # merged into runs, not one call a row
    # the refit tree's bounds are exact (not merely conservative); the wide records keep their
    # children and hold, slot by slot, the exact boxes of the binary nodes they came from; that is
    # what the GPU holds
    records = renderer.records
    bvh, nodes, wide = records.acceleration, records.nodes, records.wide
    expected_min, expected_max = bvh_bounds_from_scratch(bvh, triangle_corners(records.triangles))
    np.testing.assert_array_equal(bvh.bounds_min, expected_min)
    np.testing.assert_array_equal(bvh.bounds_max, expected_max)
    np.testing.assert_array_equal(nodes["children"], nodes_before["children"])
    used = wide.slot_node != EMPTY_SLOT
    for k, axis in enumerate("xyz"):
        np.testing.assert_array_equal(nodes[f"min_{axis}"][used], expected_min[wide.slot_node[used], k])
        np.testing.assert_array_equal(nodes[f"max_{axis}"][used], expected_max[wide.slot_node[used], k])
    np.testing.assert_array_equal(
        read_binding(renderer.context, renderer.resources["nodes"], WIDE_BVH_NODE.dtype, len(nodes)), nodes
    )
    monkeypatch.undo()  # a fresh renderer collapses its tree
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_moving_a_light_keeps_light_sampling_equal_to_a_fresh_renderer(gpu_context, monkeypatch):
    """A refit tree orders the moved light's triangles as they were; a fresh build orders them by
    where they are now. Light sampling must not see the difference."""
    scene = default_scene()
    bulb = make_icosphere((0.2, 0.7, 0.2), (0, 0, 0), 0.05, 1, Emitter("bulb", emittance=20.0), "bulb")
    scene.add(bulb)
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED)
    renderer.render(SPP)
    monkeypatch.setattr(scene_mirror, "REBUILD_DEGRADATION", np.inf)  # keep the refit tree, however poor
    bulb.transform = place((-0.4, -0.6, -0.3), (0, 0, 0), 1.0)
    image = rendered(renderer)
    assert "lights" in renderer.upload_stats and renderer._mirror.refits == 1
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_an_edit_that_restores_a_value_uploads_nothing_and_keeps_the_samples(cornell):
    scene, renderer = cornell
    red = material(scene, "red")
    red.color = red.color
    scene.shape("box1").transform = np.eye(4)
    renderer.render(SPP)
    assert renderer.upload_stats == {}
    assert renderer.samples_per_pixel == 2 * SPP


def test_adding_and_removing_shapes_rebuilds_and_switches_the_pipeline(gpu_context):
    white = Diffuse("white", color=(0.7, 0.7, 0.7))
    lamp = Emitter("lamp", color=(1, 1, 1), emittance=4.0)
    scene = Scene(
        [
            make_box((0, -1, 0), (0, 0, 0), (4, 0.1, 4), white, "floor"),
            make_box((0, 2, 0), (0, 0, 0), (1, 0.1, 1), lamp, "lamp"),
        ],
        Camera((0, 0.5, -4), (0, -0.1, 1), (0, 1, 0), 45.0),
    )
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED)
    renderer.render(SPP)
    assert "fn glass_sample" not in renderer.kernel.source.text  # no dielectric code without glass
    ball = make_icosphere((0, 0, 0), (0, 0, 0), 0.6, 1, Glass("glass", ior=1.5), "ball")
    scene.add(ball)
    image = rendered(renderer)
    assert "fn glass_sample" in renderer.kernel.source.text
    assert {"triangles", "bvh nodes", "materials", "frame"} <= set(renderer.upload_stats)
    np.testing.assert_array_equal(image, fresh_image(scene))
    scene.remove(ball)
    image = rendered(renderer)
    assert "fn glass_sample" not in renderer.kernel.source.text
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_reassigning_a_material_rewrites_only_that_shapes_triangles(cornell):
    scene, renderer = cornell
    box = scene.shape("sphere2")
    box.material = material(scene, "white")
    image = rendered(renderer)
    # glossy is still used by box2, so the material list keeps its order
    assert renderer.upload_stats == {"triangles": renderer.upload_stats["triangles"]}
    assert renderer.upload_stats["triangles"].bytes == box.triangle_count * TRIANGLE.size
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_a_refit_past_the_threshold_rebuilds(cornell, monkeypatch):
    scene, renderer = cornell
    mirror = renderer._mirror
    sphere = scene.shape("sphere1")
    sphere.transform = place((0.0, 0.0, 0.02), (0, 0, 0), 1.0)  # a small move stays a refit
    renderer.update()
    assert (mirror.refits, mirror.rebuilds) == (1, 1)
    assert mirror.refitter.degradation <= scene_mirror.REBUILD_DEGRADATION
    monkeypatch.setattr(scene_mirror, "REBUILD_DEGRADATION", 1.0)
    sphere.transform = place((0.3, 0.5, 0.3), (0, 0, 0), 1.0)
    image = rendered(renderer)
    assert (mirror.refits, mirror.rebuilds) == (1, 2)
    assert mirror.refitter.degradation == 1.0
    np.testing.assert_array_equal(image, fresh_image(scene))


def test_pipelines_are_cached_by_material_kinds(cornell):
    scene, renderer = cornell
    other = Renderer(default_scene(), SIZE, SIZE, seed=SEED + 1)
    assert other.kernel is renderer.kernel
    for name in ("fn diffuse_sample", "fn glossy_sample", "fn glass_sample"):
        assert name in renderer.kernel.source.text


def test_gpu_bytes_per_triangle_counts_every_scene_buffer(cornell):
    _, renderer = cornell
    sizes = renderer.gpu_scene_bytes
    assert set(sizes) == {"triangles", "bvh nodes", "materials", "lights"}
    triangles = renderer.triangle_count
    # no spare before the scene grows: of the triangles' texture, less than one row unused
    row_bytes = renderer.resources["triangles"].texture.size[0] * TEXEL_BYTES
    assert 0 <= sizes["triangles"] - triangles * TRIANGLE.size < row_bytes
    assert renderer.gpu_bytes_per_triangle == sum(sizes.values()) / triangles
    # triangle and node records, the nodes' texture with its spare capacity, are most of it
    nodes = len(renderer.records.nodes)
    used = triangles * TRIANGLE.size + nodes * WIDE_BVH_NODE.size
    assert used / triangles < renderer.gpu_bytes_per_triangle < (1 + SPARE_FRACTION) * used / triangles + 1


def test_a_scene_larger_than_the_adapter_allows_names_limit_and_value(gpu_context, monkeypatch):
    # 676 triangles are 2,028 texels: 32 a row, 64 rows
    monkeypatch.setitem(gpu_context.device.limits, "max-texture-dimension-2d", 63)
    with pytest.raises(
        DeviceLimitError,
        match=r"texture 'triangles' \(676 records of 48 B, 32 texels a row\) needs max-texture-dimension-2d = 64 "
        r"but the adapter .* offers 63",
    ):
        Renderer(default_scene(), SIZE, SIZE)


def test_an_edit_that_empties_the_scene_fails_and_the_renderer_recovers(cornell):
    scene, renderer = cornell
    shapes = list(scene.shapes)
    scene.remove(*shapes)
    with pytest.raises(SceneError, match="no triangles"):
        renderer.render(SPP)
    scene.add(*shapes)
    renderer.render(SPP)
    assert renderer.upload_stats == {}  # back to what the GPU holds: nothing to upload
