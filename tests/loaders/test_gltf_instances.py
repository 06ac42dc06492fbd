"""glTF nodes that share a mesh: one mesh placed by instances (the same world triangles as the
flattened Shapes), flattened where instancing cannot apply, and a node graph with a cycle refused
by the JSON path that closes it."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wgputrace import SceneLoadError, load_scene
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, MATERIALS, gltf_document, write_glb


def shared_box(tmp_path, material: int = 0, scales=((1, 1, 1), (1, 2, 1), (0.5, 0.5, 0.5))):
    """A GLB of a red box (mesh 0) referenced by one node per scale, moved apart, beside a gold box
    (mesh 1) referenced once."""
    document, blob = gltf_document(
        [(BOX, BOX_INDICES, material), (BOX, BOX_INDICES, 3)], materials=json.loads(json.dumps(MATERIALS))
    )
    document["nodes"] = [{"mesh": 1, "translation": [0, -3, 0]}] + [
        {"mesh": 0, "translation": [2.0 * k, 0, 0], "rotation": [0, 0.38268343, 0, 0.92387953], "scale": list(s)}
        for k, s in enumerate(scales)
    ]
    document["scenes"][0]["nodes"] = list(range(len(document["nodes"])))
    return write_glb(tmp_path / "shared.glb", document, blob)


def world_triangles(scene) -> np.ndarray:
    return np.concatenate([shape.world_vertices for shape in scene.flattened().shapes])


def test_nodes_sharing_a_mesh_become_instances_of_one_mesh(tmp_path):
    scene = load_scene(shared_box(tmp_path))
    assert [shape.name for shape in scene.shapes] == ["mesh1"]  # referenced once: a Shape as before
    assert [instance.name for instance in scene.instances] == [f"mesh0@nodes[{k}]" for k in (1, 2, 3)]
    assert len({id(instance.mesh) for instance in scene.instances}) == 1
    np.testing.assert_allclose(scene.instances[1].transform[:3, 3], [2, 0, 0])
    flat = world_triangles(scene)
    np.testing.assert_allclose(
        flat[12:24], scene.instances[0].mesh.transformed(scene.instances[0].transform).world_vertices
    )
    assert len(flat) == 4 * len(BOX_INDICES)


@pytest.mark.parametrize(
    ("material", "scales", "flattened"),
    [
        (2, ((1, 1, 1), (1, 1, 1)), 2),  # an emitting mesh: the light sampler needs it in the world
        (0, ((1, 1, 1), (-1, 1, 1)), 1),  # a mirroring node: only the mirrored reference
    ],
)
def test_emitting_meshes_and_mirroring_nodes_stay_flattened(tmp_path, material, scales, flattened):
    scene = load_scene(shared_box(tmp_path, material, scales))
    assert len(scene.shapes) == 1 + flattened
    assert len(scene.instances) == len(scales) - flattened


def test_a_file_of_shared_meshes_alone_keeps_one_shape(tmp_path):
    document, blob = gltf_document([(BOX, BOX_INDICES, 0)], materials=json.loads(json.dumps(MATERIALS)))
    document["nodes"] = [{"mesh": 0, "translation": [2.0 * k, 0, 0]} for k in range(3)]
    document["scenes"][0]["nodes"] = [0, 1, 2]
    scene = load_scene(write_glb(tmp_path / "only.glb", document, blob))
    assert len(scene.shapes) == 1 and len(scene.instances) == 2
    assert scene.camera.position[0] == pytest.approx(2.0)  # framed around the instances too


def test_a_cycle_in_the_node_graph_names_the_child_that_closes_it(tmp_path):
    document, blob = gltf_document([(BOX, BOX_INDICES, 0)], materials=json.loads(json.dumps(MATERIALS)))
    document["nodes"] = [{"children": [1]}, {"mesh": 0, "children": [2]}, {"children": [0]}]
    document["scenes"][0]["nodes"] = [0]
    path = write_glb(tmp_path / "cycle.glb", document, blob)
    with pytest.raises(SceneLoadError) as raised:
        load_scene(path)
    message = str(raised.value)
    assert str(path) in message and "\n" not in message
    assert "nodes[2].children[0]: is node 0, its own ancestor: the node graph has a cycle" in message
