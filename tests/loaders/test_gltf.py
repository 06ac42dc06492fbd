"""glTF/GLB: the documented material mapping, node transforms as shape transforms, the camera, strips
and fans, and errors that name the file and the JSON path of what is wrong."""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest

from wgputrace import (
    Camera,
    Diffuse,
    Emitter,
    Glossy,
    OrthographicCamera,
    Principled,
    SceneLoadError,
    SceneLoadWarning,
    load_scene,
)
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, MATERIALS, gltf_document, write_glb, write_gltf


def box_document(count: int = 5, **extra) -> tuple[dict, bytes]:
    materials = [0, 1, 2, 3, None][:count]
    return gltf_document(
        [(BOX, BOX_INDICES, m) for m in materials], materials=json.loads(json.dumps(MATERIALS)), **extra
    )


@pytest.mark.parametrize("writer", [write_glb, write_gltf])
def test_materials_transforms_and_camera(tmp_path, writer):
    document, blob = box_document(cameras=[{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}])
    document["nodes"][1]["translation"] = [2, 0, 0]
    document["nodes"][2]["rotation"] = [0, math.sin(math.pi / 4), 0, math.cos(math.pi / 4)]  # 90 deg about y
    document["nodes"][3]["matrix"] = [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, -3, 1]  # column-major
    document["nodes"].append({"camera": 0, "translation": [0, 1, 5], "rotation": [0, 0, 0, 1]})
    document["scenes"][0]["nodes"].append(5)
    scene = load_scene(writer(tmp_path / ("boxes.glb" if writer is write_glb else "boxes.gltf"), document, blob))
    m = [shape.material for shape in scene.shapes]
    assert isinstance(m[0], Diffuse) and m[0].color == (1.0, 0.0, 0.0)
    assert isinstance(m[1], Principled) and (m[1].spec_trans, m[1].eta, m[1].metallic) == (1.0, 1.33, 0.0)
    assert m[1].base_color == pytest.approx((0.9, 0.9, 1.0)) and m[1].roughness == 1.0  # glTF's default
    assert isinstance(m[2], Emitter) and (m[2].color, m[2].emittance) == ((1.0, 0.5, 0.25), 8.0)
    assert isinstance(m[3], Glossy) and m[3].roughness == 0.25  # metallicFactor defaults to 1; alpha = 0.5^2
    assert isinstance(m[4], Diffuse) and m[4].color == (0.8, 0.8, 0.8)
    np.testing.assert_allclose(scene.shapes[1].world_vertices.mean(axis=(0, 1)), [2, 0, 0], atol=1e-6)
    np.testing.assert_allclose(scene.shapes[2].transform[:3, :3], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-12)
    np.testing.assert_allclose(scene.shapes[3].world_vertices.max(axis=(0, 1)), [1, 1, -2], atol=1e-6)
    np.testing.assert_allclose(scene.camera.position, [0, 1, 5])
    np.testing.assert_allclose(scene.camera.forward, [0, 0, -1])
    assert scene.camera.vfov_degrees == pytest.approx(math.degrees(0.8))


def test_an_orthographic_camera_is_the_orthographic_kind(tmp_path):
    """glTF's ymag is half the view's height, in the camera node's units (its y scale applies); the
    image's own aspect sets the width, xmag is not read."""
    ortho = {"type": "orthographic", "orthographic": {"xmag": 3.0, "ymag": 1.5, "znear": 0.1, "zfar": 50.0}}
    document, blob = box_document(1, cameras=[ortho])
    quarter_turn = [-math.sin(math.pi / 4), 0, 0, math.cos(math.pi / 4)]  # -90 deg about x: looking down
    document["nodes"].append({"camera": 0, "translation": [0, 4, 0], "rotation": quarter_turn, "scale": [2, 2, 2]})
    document["scenes"][0]["nodes"].append(len(document["nodes"]) - 1)
    scene = load_scene(write_glb(tmp_path / "ortho.glb", document, blob))
    assert isinstance(scene.camera, OrthographicCamera)
    assert scene.camera.view_height == pytest.approx(2 * 1.5 * 2)
    np.testing.assert_allclose(scene.camera.position, [0, 4, 0])
    np.testing.assert_allclose(scene.camera.forward, [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(scene.camera.up, [0, 0, -2], atol=1e-12)


def test_a_camera_of_another_type_warns_and_the_scene_is_framed(tmp_path):
    document, blob = box_document(1, cameras=[{"type": "fisheye", "fisheye": {}}])
    document["nodes"].append({"camera": 0, "translation": [0, 1, 5]})
    document["scenes"][0]["nodes"].append(len(document["nodes"]) - 1)
    with pytest.warns(
        SceneLoadWarning, match=r"cameras\[0\] is of type 'fisheye', neither perspective nor orthographic"
    ):
        scene = load_scene(write_glb(tmp_path / "fisheye.glb", document, blob))
    assert type(scene.camera) is Camera and scene.camera.forward == (0.0, 0.0, -1.0)


def test_without_a_camera_the_scene_is_framed_from_plus_z(tmp_path):
    document, blob = box_document(1)
    scene = load_scene(write_glb(tmp_path / "box.glb", document, blob))
    assert scene.camera.forward == (0.0, 0.0, -1.0) and scene.camera.position[2] > 0.5


def test_strips_and_fans_keep_the_winding(tmp_path):
    square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
    document, blob = gltf_document([(square, np.array([0, 1, 2, 3]), None), (square, np.array([0, 1, 3, 2]), None)])
    document["meshes"][0]["primitives"][0]["mode"] = 5
    document["meshes"][1]["primitives"][0]["mode"] = 6
    strip, fan = load_scene(write_glb(tmp_path / "modes.glb", document, blob)).shapes
    for shape in (strip, fan):
        v = shape.vertices.astype(np.float64)
        normals = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        np.testing.assert_allclose(normals, [[0, 0, 1], [0, 0, 1]])  # both triangles face +z


def corrupt(document: dict, change) -> dict:
    change(document)
    return document


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda d: d["accessors"][0].update(count=1000), r"accessors\[0\]: reads 12000 bytes of bufferViews\[0\]"),
        (lambda d: d["accessors"][1].update(componentType=5126), r"indices -> accessors\[1\]: must be"),
        (lambda d: d["meshes"][0]["primitives"][0].pop("attributes"), r"primitives\[0\]: 'attributes' is missing"),
        (lambda d: d["meshes"][0]["primitives"][0].update(indices=99), r"accessors index 99 out of range"),
        (lambda d: d["nodes"][0].update(children=[0]), r"nodes\[0\]\.children\[0\]: is node 0, its own ancestor"),
        (lambda d: d["nodes"][0].update(matrix=[1] * 15), r"nodes\[0\].matrix: must be 16 numbers"),
        (lambda d: d["nodes"][0].update(scale=[0, 0, 0]), "determinant 0.0"),
        (lambda d: d["accessors"][0].update(sparse={}), "sparse accessors are not supported"),
        (lambda d: d["bufferViews"][0].update(byteLength=10**9), r"bufferViews\[0\]: bytes 0..1000000000 lie beyond"),
        (
            lambda d: d["materials"][1]["extensions"]["KHR_materials_ior"].update(ior=0),
            r"materials\[1\]: .*eta must be",
        ),
        (lambda d: d["materials"][0]["pbrMetallicRoughness"].update(baseColorFactor=[1, -1, 0, 1]), "color must be"),
        (lambda d: d["materials"][3]["pbrMetallicRoughness"].update(roughnessFactor="rough"), "must be float"),
        (lambda d: d.update(scenes=[{"nodes": [9]}]), r"nodes index 9 out of range"),
    ],
)
def test_errors_name_file_and_json_path(tmp_path, change, message):
    document, blob = box_document(4)
    path = write_glb(tmp_path / "bad.glb", corrupt(document, change), blob)
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(path)
    assert caught.value.path == path and str(caught.value).startswith(f"{path}: ")


def test_broken_containers_are_named(tmp_path):
    document, blob = box_document(1)
    good = write_glb(tmp_path / "good.glb", document, blob).read_bytes()
    cases = {
        "truncated.glb": (good[: len(good) // 2], "truncated"),
        "version.glb": (good[:4] + struct.pack("<I", 1) + good[8:], "GLB version 1"),
        "json.glb": (good[:20] + b"{" * 4 + good[24:], "the glTF JSON does not parse"),
        "tiny.glb": (good[:10], "shorter than its 12-byte header"),
    }
    for name, (data, message) in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(SceneLoadError, match=message):
            load_scene(tmp_path / name)
    (tmp_path / "text.gltf").write_text('{"asset": {"version": "2.0"},\n "nodes": [}')
    with pytest.raises(SceneLoadError, match="does not parse") as caught:
        load_scene(tmp_path / "text.gltf")
    assert caught.value.line == 2


def test_points_and_lines_are_skipped_with_a_warning(tmp_path):
    document, blob = box_document(2)
    document["meshes"][1]["primitives"][0]["mode"] = 1
    with pytest.warns(SceneLoadWarning, match=r"meshes\[1\].primitives\[0\] has mode 1 \(points or lines\): skipped"):
        scene = load_scene(write_glb(tmp_path / "lines.glb", document, blob))
    assert len(scene.shapes) == 1


def test_unknown_format_and_missing_file(tmp_path):
    with pytest.raises(SceneLoadError, match=r"unknown scene format '.fbx'; wgputrace reads .obj, .gltf"):
        load_scene(tmp_path / "model.fbx")
    with pytest.raises(SceneLoadError, match="no such file"):
        load_scene(tmp_path / "missing.glb")
