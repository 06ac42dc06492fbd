"""glTF extensions: a required one the loader does not read is refused by name (with what it is and
how to get support), one only used is ignored with a warning, and KHR_draco_mesh_compression
primitives are decoded when DracoPy (the `draco` extra) is installed."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

from wgputrace import SceneLoadError, load_scene
from wgputrace.loaders.errors import SceneLoadWarning
from wgputrace.loaders.gltf import _Reader
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, MATERIALS, gltf_document, write_glb

DRACO = "KHR_draco_mesh_compression"
# Draco keeps positions to 2^-bits of the box's extent (1): this bound is a quarter of a step
# above the rounding error of 14 bits.
DRACO_POSITION_BITS = 14
DRACO_TOLERANCE = 2.0**-DRACO_POSITION_BITS
FLOAT, UNSIGNED_INT = 5126, 5125


def box_file(path, **extra):
    """A GLB of the unit box with one diffuse material; `extra` adds or replaces top-level keys."""
    return write_glb(path, *gltf_document([(BOX, BOX_INDICES, 0)], materials=MATERIALS[:1], **extra))


def without_dracopy(monkeypatch):
    monkeypatch.setitem(sys.modules, "DracoPy", None)  # `import DracoPy` then raises ImportError


@pytest.fixture
def without_basisu(monkeypatch):
    """KHR_texture_basisu unread, as without the `ktx2` extra: the example of a known extension refused."""
    monkeypatch.setitem(sys.modules, "opengl_basisu", None)


@pytest.mark.parametrize(
    "extension, said",
    [
        (
            "KHR_texture_basisu",
            'KHR_texture_basisu (KTX2 textures): needs opengl-basisu: pip install "wgputrace[ktx2]"',
        ),
        ("EXT_made_up", "EXT_made_up"),
    ],
)
def test_a_required_extension_not_read_is_refused_by_name(tmp_path, without_basisu, extension, said):
    path = box_file(tmp_path / "box.glb", extensionsUsed=[extension], extensionsRequired=[extension])
    with pytest.raises(SceneLoadError, match="extensionsRequired") as caught:
        load_scene(path)
    assert str(caught.value).startswith(str(path))
    assert said in str(caught.value)


def test_every_required_extension_not_read_is_named_in_one_error(tmp_path, without_basisu):
    required = ["KHR_lights_punctual", "KHR_texture_basisu", "EXT_made_up"]
    path = box_file(tmp_path / "box.glb", extensionsUsed=required, extensionsRequired=required)
    with pytest.raises(SceneLoadError) as caught:
        load_scene(path)
    message = str(caught.value)
    assert "KHR_texture_basisu" in message and "EXT_made_up" in message
    assert "KHR_lights_punctual" not in message


def test_a_draco_file_without_dracopy_says_how_to_install_it(tmp_path, monkeypatch):
    without_dracopy(monkeypatch)
    path = box_file(tmp_path / "box.glb", extensionsUsed=[DRACO], extensionsRequired=[DRACO])
    with pytest.raises(SceneLoadError) as caught:
        load_scene(path)
    assert f'{DRACO} (Draco-compressed meshes): needs DracoPy: pip install "wgputrace[draco]"' in str(caught.value)


def test_extensions_the_loader_reads_may_be_required(tmp_path):
    read = ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior"]
    path = box_file(tmp_path / "box.glb", extensionsUsed=read, extensionsRequired=read)
    with warnings.catch_warnings():
        warnings.simplefilter("error", SceneLoadWarning)
        scene = load_scene(path)
    assert len(scene.shapes) == 1


def test_an_extension_only_used_is_ignored_with_a_warning_naming_it(tmp_path, without_basisu):
    path = box_file(tmp_path / "box.glb", extensionsUsed=["KHR_texture_basisu", "EXT_made_up", "KHR_lights_punctual"])
    with pytest.warns(SceneLoadWarning, match=r"KHR_texture_basisu \(KTX2 textures\), EXT_made_up not supported"):
        scene = load_scene(path)
    np.testing.assert_array_equal(scene.shapes[0].vertices.reshape(-1, 3), BOX[BOX_INDICES].reshape(-1, 3))


@pytest.mark.parametrize("value", ["KHR_lights_punctual", [1], [None]])
def test_an_extension_list_must_hold_names(tmp_path, value):
    path = box_file(tmp_path / "box.glb", extensionsRequired=value)
    with pytest.raises(SceneLoadError, match="extensionsRequired"):
        load_scene(path)


def draco_box(tmp_path, encoded: bytes, required: bool = True):
    """A GLB whose one primitive is the Draco mesh `encoded` (POSITION, NORMAL, TEXCOORD_0 and
    indices), its accessors without data of their own."""
    import DracoPy

    ids = {entry["attribute_type"]: entry["unique_id"] for entry in DracoPy.decode(encoded).attributes}
    names = {
        "POSITION": (DracoPy.AttributeType.POSITION, "VEC3"),
        "NORMAL": (DracoPy.AttributeType.NORMAL, "VEC3"),
        "TEXCOORD_0": (DracoPy.AttributeType.TEX_COORD, "VEC2"),
    }
    accessors = [{"componentType": FLOAT, "count": len(BOX), "type": kind} for _, kind in names.values()]
    accessors.append({"componentType": UNSIGNED_INT, "count": BOX_INDICES.size, "type": "SCALAR"})
    draco = {"bufferView": 0, "attributes": {name: ids[kind] for name, (kind, _) in names.items()}}
    primitive = {
        "attributes": {name: number for number, name in enumerate(names)},
        "indices": 3,
        "material": 0,
        "extensions": {DRACO: draco},
    }
    document, _ = gltf_document([], materials=MATERIALS[:1])
    document.update(
        meshes=[{"name": "box", "primitives": [primitive]}],
        nodes=[{"mesh": 0}],
        scenes=[{"nodes": [0]}],
        accessors=accessors,
        bufferViews=[{"buffer": 0, "byteLength": len(encoded)}],
        buffers=[{"byteLength": len(encoded)}],
        extensionsUsed=[DRACO],
        **({"extensionsRequired": [DRACO]} if required else {}),
    )
    return write_glb(tmp_path / "draco.glb", document, encoded)


def box_attributes():
    """The box's corner normals (its face normals) and texture coordinates (its x and y)."""
    corners = BOX[BOX_INDICES]
    faces = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals = np.repeat(faces / np.linalg.norm(faces, axis=1, keepdims=True), 3, axis=0)
    # DracoPy takes float64 attributes only
    return normals.astype(np.float64), BOX[:, :2].astype(np.float64)


def test_a_draco_box_loads_its_triangles_normals_and_texture_coordinates(tmp_path):
    DracoPy = pytest.importorskip("DracoPy")
    normals, uvs = box_attributes()
    encoded = DracoPy.encode(BOX, BOX_INDICES, DRACO_POSITION_BITS, preserve_order=True, normals=normals, tex_coord=uvs)
    path = draco_box(tmp_path, encoded)
    (shape,) = load_scene(path).shapes
    np.testing.assert_allclose(shape.vertices.reshape(-1, 3, 3), BOX[BOX_INDICES], atol=DRACO_TOLERANCE)
    np.testing.assert_allclose(shape.normals, normals[BOX_INDICES], atol=DRACO_TOLERANCE)
    # Texture coordinates are not read into shapes yet: the accessor the loader will read them from
    where = "meshes[0].primitives[0].attributes.TEXCOORD_0"
    np.testing.assert_allclose(_Reader(path).accessor(2, where, (FLOAT,), ("VEC2",)), uvs, atol=DRACO_TOLERANCE)


def test_draco_bytes_that_do_not_decode_name_their_buffer_view(tmp_path):
    DracoPy = pytest.importorskip("DracoPy")
    encoded = DracoPy.encode(BOX, BOX_INDICES, normals=box_attributes()[0], tex_coord=box_attributes()[1])
    path = draco_box(tmp_path, encoded)
    data = bytearray(path.read_bytes())
    start = data.index(encoded)
    data[start : start + 16] = b"\0" * 16  # the Draco header
    path.write_bytes(bytes(data))
    with pytest.raises(SceneLoadError, match=rf"extensions.{DRACO}.bufferView: the Draco bytes do not decode"):
        load_scene(path)


def test_a_file_only_using_draco_loads_its_uncompressed_data_without_dracopy(tmp_path, monkeypatch):
    without_dracopy(monkeypatch)
    document, blob = gltf_document([(BOX, BOX_INDICES, 0)], materials=MATERIALS[:1], extensionsUsed=[DRACO])
    # Draco bytes that would not decode: the loader must not look at them
    document["bufferViews"].append({"buffer": 0, "byteLength": 4})
    document["meshes"][0]["primitives"][0]["extensions"] = {DRACO: {"bufferView": 2, "attributes": {"POSITION": 0}}}
    path = write_glb(tmp_path / "fallback.glb", document, blob)
    with pytest.warns(SceneLoadWarning, match=rf"{DRACO} \(Draco-compressed meshes\) not supported"):
        (shape,) = load_scene(path).shapes
    np.testing.assert_array_equal(shape.vertices.reshape(-1, 3), BOX[BOX_INDICES].reshape(-1, 3))
