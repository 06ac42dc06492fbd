"""Instances on the GPU: the two-level traversal draws what the flattened scene draws, finds the
nearest of overlapping instances, and a transform edit refits only the top level.

Same picture, two ways. Where the instances' transforms are identities the GPU's arithmetic is
exact (x * 1 + y * 0 + z * 0 + 0 is x), so the instanced and the flattened scene render bit for
bit alike: that checks the plumbing (hit words, per-triangle attributes fetched by the mesh's
triangle, materials, shading normals) with nothing left to chance. Turned, stretched and moved
instances intersect in object space, whose float32 rounding differs from the flattened
triangles' (a ray origin moved into object space is rounded; the flattened corners were rounded
once in float64), so there the two images are independent estimates of one picture: a block
Welch test on batches of seeds.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, PointLight, Renderer, Scene, make_box, make_plane, model_matrix
from wgputrace.scenes import scene_by_name
from wgputrace.scenes.instanced import instanced_cornell
from wgputrace.testing.image_statistics import BLOCKS, CHANNELS, Estimate, compare_blocks

SIZE = 32
SEED = 3
SPP = 4
# Welch test: batches of independent seeds per image, the family-wise significance level, and its
# Sidak correction over the blocks and channels tested
BATCHES = 8
BATCH_SPP = 8
SIGNIFICANCE = 1e-3
PER_TEST_LEVEL = 1.0 - (1.0 - SIGNIFICANCE) ** (1.0 / (BLOCKS * BLOCKS * CHANNELS))


def image(scene: Scene, seed: int = SEED, spp: int = SPP) -> np.ndarray:
    renderer = Renderer(scene, SIZE, SIZE, seed=seed)
    renderer.render(spp)
    return renderer.image()


def at_identity(scene: Scene) -> Scene:
    """`scene` with every instance replaced by one of its own flattened mesh at the identity."""
    placed = Scene(list(scene.shapes), scene.camera, scene.environment)
    for instance in scene.instances:
        placed.add_instance(instance.flattened(), np.eye(4), instance.name)
    return placed


def shapes_as_instances(scene: Scene) -> Scene:
    """`scene` with each of its shapes that does not emit drawn by an instance at the identity (the
    shape its mesh), and a small grey square behind the camera where no shape is left."""
    kept = [shape for shape in scene.shapes if shape.material.emits()]
    behind = np.asarray(scene.camera.position) - 2.0 * np.asarray(scene.camera.forward)
    kept = kept or [make_plane(behind, (0, 0, 0), (0.1, 0.1), Diffuse("anchor", (0.5, 0.5, 0.5)), "anchor")]
    placed = Scene(kept, scene.camera, scene.environment)
    placed.add_light(*scene.lights)
    for shape in scene.shapes:
        if not shape.material.emits():
            placed.add_instance(shape, np.eye(4), shape.name)
    return placed


def coloured_cornell() -> Scene:
    """The instanced Cornell box at the identity, its spheres with vertex colours."""
    scene = at_identity(instanced_cornell())
    for instance in scene.instances:
        corners = instance.mesh.world_vertices
        instance.mesh.colors = np.concatenate([0.5 + 0.5 * np.sin(4 * corners), np.ones_like(corners[..., :1])], -1)
    return scene


@pytest.mark.parametrize(
    "make",
    [
        pytest.param(lambda: at_identity(instanced_cornell()), id="smooth normals"),
        pytest.param(coloured_cornell, id="vertex colours", marks=pytest.mark.slow),
        pytest.param(
            lambda: shapes_as_instances(scene_by_name("textured_quads")), id="textures", marks=pytest.mark.slow
        ),
        pytest.param(
            lambda: shapes_as_instances(scene_by_name("normal_mapped_plane")), id="normal map", marks=pytest.mark.slow
        ),
        pytest.param(
            lambda: shapes_as_instances(scene_by_name("alpha_cutout")), id="alpha cut-out", marks=pytest.mark.slow
        ),
    ],
)
def test_instances_at_the_identity_render_the_flattened_picture_bit_for_bit(gpu_context, make):
    scene = make()
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED)
    assert "instances" in renderer.variant.scene.labels
    renderer.render(SPP)
    np.testing.assert_array_equal(renderer.image(), image(scene.flattened()))


def turned_normal_map() -> Scene:
    """The normal-mapped plane drawn by an instance turned about the view axis and shrunk: its
    tangents (MikkTSpace's, in object space) must follow the transform as the flattened plane's do."""
    scene = scene_by_name("normal_mapped_plane")
    placed = shapes_as_instances(scene)
    placed.instances[0].transform = model_matrix((0.1, -0.05, 0), (0, 0, 0.7), (0.9, 0.8, 1.0))
    return placed


@pytest.mark.slow
@pytest.mark.parametrize(
    "make",
    [pytest.param(instanced_cornell, id="normals"), pytest.param(turned_normal_map, id="tangents")],
)
def test_placed_instances_render_the_flattened_picture(gpu_context, make):
    scene = make()
    estimates = [
        Estimate.from_batches([image(s, seed=SEED + 100 * k, spp=BATCH_SPP) for k in range(BATCHES)])
        for s in (scene, scene.flattened())
    ]
    comparison = compare_blocks(*estimates, SIZE // BLOCKS)
    assert comparison.p_value.min() > PER_TEST_LEVEL, f"blocks differ: z = {comparison.z.round(2).tolist()}"


def overlapping_boxes() -> tuple[Scene, object]:
    """A red box and a green one overlapping it nearer the camera, both instances, before a grey
    wall, lit by a point light (whose power, unlike a sky's, does not follow the scene's size);
    returns the scene and the green instance."""
    room = make_plane((0, 0, 3), (-np.pi / 2, 0, 0), (20, 20), Diffuse("grey", (0.5, 0.5, 0.5)), "back")
    scene = Scene([room], Camera.looking_at((0, 0, -5), (0, 0, 0), vfov_degrees=20.0))
    scene.add_light(PointLight((0, 3, -4), 50.0))
    red = make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("red", (0.9, 0.1, 0.1)), "red")
    green = make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("green", (0.1, 0.9, 0.1)), "green")
    scene.add_instance(red, model_matrix((0, 0, 0), (0, 0, 0), 2.0))
    # the same mesh twice more, overlapping: the one turned towards the camera is nearer
    scene.add_instance(red, model_matrix((0.3, 0.2, 0.4), (0.3, 0.4, 0), 2.0))
    return scene, scene.add_instance(green, model_matrix((0, 0, -0.8), (0, 0, np.pi / 4), 1.5))


def centre_albedo(renderer: Renderer) -> np.ndarray:
    renderer.render(SPP)
    return renderer.guides()["albedo"][SIZE // 2, SIZE // 2]


def test_the_nearest_of_overlapping_instances_is_hit_and_a_move_refits_only_the_top_level(gpu_context):
    scene, green = overlapping_boxes()
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, guides=True)
    np.testing.assert_allclose(centre_albedo(renderer), (0.1, 0.9, 0.1), atol=1e-6)
    mirror = renderer._mirror
    rebuilds, top_records = mirror.rebuilds, mirror.instancing.top_records
    green.transform = model_matrix((0, 0, 1.2), (0, 0, np.pi / 4), 1.5)  # behind the red ones now
    np.testing.assert_allclose(centre_albedo(renderer), (0.9, 0.1, 0.1), atol=1e-6)
    stats = renderer.upload_stats
    assert set(stats) == {"bvh nodes", "instances"}, stats
    assert mirror.rebuilds == rebuilds and stats["instances"].bytes <= 2 * mirror.instancing.records.itemsize
    # only top-level records went up (they come first in the nodes)
    assert stats["bvh nodes"].bytes <= top_records * mirror.instancing.top_nodes.itemsize
    fresh = Renderer(scene, SIZE, SIZE, seed=SEED, guides=True)
    fresh.render(SPP)
    np.testing.assert_array_equal(renderer.image(), fresh.image())


def test_an_emitting_instanced_mesh_is_refused_by_name(gpu_context):
    from wgputrace import Emitter
    from wgputrace.scene import SceneError

    scene, _ = overlapping_boxes()
    lamp = make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Emitter("lamp", (1, 1, 1), emittance=5.0), "lamp")
    scene.add_instance(lamp, np.eye(4), "lamp0")
    with pytest.raises(SceneError, match="instance 'lamp0': its mesh 'lamp' emits light.*flattened"):
        Renderer(scene, SIZE, SIZE)
