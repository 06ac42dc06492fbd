"""Property-based fuzzing of the loaders: random and mutated OBJ/MTL text (texture maps and `vt`
included), truncated and garbled GLB (an embedded PNG texture included), PLY and STL files, and
glTF JSON (materials, textures, samplers, images, nodes, vertex colours, perspective and orthographic
cameras, KHR_lights_punctual lights and the extension lists) with random values in random places, and
meshopt-compressed GLB (its bufferView and buffer JSON randomised, its compressed bytes garbled). Then
the fields the issue names, with values at and past their limits: camera yfov, aspectRatio, xmag,
ymag, znear and zfar; meshopt filters, modes, strides, counts and truncated streams; COLOR_0
accessors of wrong types, counts and values; and truncated or garbled KTX2 textures. Every input
must end in a Scene or a one-line SceneLoadError (naming the JSON path where only the JSON was
mutated), within a time limit: no other exception, no hang, no NaN or infinity in a shape, a light
or a camera. Mutated Cornell boxes that load are rendered (4x4, one sample): no NaN reaches the image."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
import trimesh
from hypothesis import given
from hypothesis import strategies as st

from wgputrace import Scene, SceneLoadError, load_scene, render
from wgputrace.scene import DegenerateTrianglesWarning
from wgputrace.testing.fuzz_loading import outcome
from wgputrace.testing.fuzzing import fuzz_settings, time_limit
from wgputrace.testing.gltf_files import (
    BOX,
    BOX_INDICES,
    CAMERA_NODES,
    CAMERAS,
    LIGHTS,
    MATERIALS,
    gltf_document,
    light_node,
    marked_pixels,
    png_bytes,
    textured_square,
    with_cameras,
    with_lights,
    with_vertex_attribute,
    write_glb,
)
from wgputrace.testing.ktx2_files import encode_ktx2, ktx2_textured_square
from wgputrace.testing.meshopt_files import KHR, meshopt_compressed

# Examples per test, chosen so the whole file stays within ~20 s on a 2-core CI machine (JSON
# mutations are cheapest to check and reach the most code paths per example).
TEXT_EXAMPLES = 200
BINARY_EXAMPLES = 200
JSON_EXAMPLES = 500
TEXTURED_JSON_EXAMPLES = 200
CAMERA_JSON_EXAMPLES = 100
MESHOPT_EXAMPLES = 200
FIELD_EXAMPLES = 100
RENDER_SIZE = 4

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr),
    st.integers(-12, 12).map(str),
    st.sampled_from(["1e39", "-0", "nan", "inf", "0x1p3", "1_0", "", "--1", "1e-45"]),
)
names = st.text(st.characters(blacklist_categories=["Cs"]), max_size=8)
face_reference = st.tuples(st.integers(-12, 12), st.sampled_from(["", "/1", "//1", "/1/1", "/", "/x"])).map(
    lambda t: f"{t[0]}{t[1]}"
)
obj_line = st.one_of(
    st.lists(numbers, min_size=0, max_size=7).map(lambda n: " ".join(["v", *n])),  # with colours: 6
    st.lists(face_reference, min_size=0, max_size=6).map(lambda r: " ".join(["f", *r])),
    names.map(lambda n: f"o {n}"),
    names.map(lambda n: f"g {n}"),
    st.sampled_from(["usemtl a", "usemtl b", "usemtl", "mtllib m.mtl", "mtllib missing.mtl", "# c", "s 1", "vt 0 0"]),
    st.lists(numbers, min_size=0, max_size=3).map(lambda n: " ".join(["vt", *n])),
    st.text(max_size=30),
)
mtl_line = st.one_of(
    st.tuples(
        st.sampled_from(["Kd", "Ks", "Ke", "Tf", "Ns", "Ni", "d", "Tr", "Pr", "Pm", "illum", "Ka", "map_Kd"]),
        st.lists(numbers, min_size=0, max_size=4),
    ).map(lambda t: " ".join([t[0], *t[1]])),
    st.tuples(
        st.sampled_from(["map_Kd", "map_Ks", "map_Pr", "map_Pm", "map_Ke", "map_d", "bump", "map_Bump", "norm"]),
        st.lists(st.sampled_from(["-clamp", "on", "-bm", "-s", "-o", "-imfchan", "r"]) | numbers, max_size=3),
        st.sampled_from(["t.png", "grey.png", "garbled.png", "missing.png", ""]),
    ).map(lambda t: " ".join([t[0], *t[1], t[2]])),
    st.sampled_from(["newmtl a", "newmtl b", "newmtl"]),
    st.text(max_size=20),
)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


def lit_boxes() -> tuple[dict, bytes]:
    """Two boxes (a red diffuse one with vertex colours and a gold glossy one), one light of each
    type, the spot turned by its node, the lights' extension required, and a perspective and an
    orthographic camera, as a JSON document and its buffer."""
    document, blob = gltf_document(
        [(BOX, BOX_INDICES, 0), (BOX, BOX_INDICES, 3)], materials=MATERIALS, extensionsRequired=["KHR_lights_punctual"]
    )
    blob = with_vertex_attribute(document, blob, 0, "COLOR_0", np.linspace(0, 1, 4 * len(BOX)).reshape(-1, 4))
    nodes = [light_node(0, translation=[0, 3, 0]), light_node(1, rotation=[0.5, 0.5, 0.5, 0.5]), light_node(2)]
    document = with_lights(json.loads(json.dumps(document)), json.loads(json.dumps(LIGHTS)), nodes)
    return with_cameras(document, *json.loads(json.dumps([CAMERAS, CAMERA_NODES]))), blob


@pytest.fixture(scope="module")
def map_images(workdir) -> None:
    """The images the random MTL maps name: a colour one, a grey one and a garbled one."""
    (workdir / "t.png").write_bytes(png_bytes(marked_pixels()))
    (workdir / "grey.png").write_bytes(png_bytes(np.full((3, 5, 1), 90, np.uint8)))
    (workdir / "garbled.png").write_bytes(png_bytes(marked_pixels(16))[:70])


@fuzz_settings(TEXT_EXAMPLES)
@given(obj=st.lists(obj_line, max_size=25), mtl=st.lists(mtl_line, max_size=15))
def test_random_obj_and_mtl_text(workdir, map_images, obj, mtl):
    (workdir / "m.mtl").write_text("\n".join(mtl))
    (workdir / "random.obj").write_text("\n".join(obj))
    outcome(workdir / "random.obj")


TEXTURED_QUAD_OBJ = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nusemtl a\nf 1/1 2/2 3/2 4/1\n"


@fuzz_settings(TEXT_EXAMPLES)
@given(mtl=st.lists(mtl_line, max_size=8))
def test_random_mtl_of_a_textured_quad(workdir, map_images, mtl):
    """A valid quad with texture coordinates, so that the random material statements are mapped."""
    (workdir / "m.mtl").write_text("\n".join(["newmtl a", *mtl]))
    (workdir / "quad.obj").write_text(TEXTURED_QUAD_OBJ)
    outcome(workdir / "quad.obj")


@pytest.fixture(scope="module")
def cornell_text(data_dir) -> str:
    return (data_dir / "cornell_trac0r.obj").read_text()


@pytest.mark.gpu  # what loads is rendered
@fuzz_settings(TEXT_EXAMPLES)
@given(data=st.data())
def test_mutated_cornell_obj(workdir, data_dir, cornell_text, data):
    lines = cornell_text.splitlines()
    for _ in range(data.draw(st.integers(1, 4))):
        index = data.draw(st.integers(0, len(lines) - 1))
        kind = data.draw(st.sampled_from(["delete", "duplicate", "replace", "token"]))
        if kind == "delete":
            del lines[index]
        elif kind == "duplicate":
            lines.insert(index, lines[index])
        elif kind == "replace":
            lines[index] = data.draw(obj_line)
        else:
            tokens = lines[index].split() or [""]
            tokens[data.draw(st.integers(0, len(tokens) - 1))] = data.draw(numbers | names)
            lines[index] = " ".join(tokens)
    text = "\n".join(lines).encode()
    text = text[: data.draw(st.integers(0, len(text)))] if data.draw(st.booleans()) else text
    (workdir / "cornell_trac0r.mtl").write_bytes((data_dir / "cornell_trac0r.mtl").read_bytes())
    (workdir / "mutated.obj").write_bytes(text)
    scene = outcome(workdir / "mutated.obj")
    if isinstance(scene, Scene):  # whatever loads renders, and no NaN reaches the image
        with time_limit(), warnings.catch_warnings():
            warnings.simplefilter("ignore", DegenerateTrianglesWarning)
            assert np.all(np.isfinite(render(scene, 1, RENDER_SIZE, RENDER_SIZE)))


@pytest.fixture(scope="module")
def originals(workdir) -> dict[str, bytes]:
    """A small valid file of each binary format, to cut and garble."""
    mesh = trimesh.Trimesh(BOX, BOX_INDICES, process=False)
    document, blob = lit_boxes()
    return {
        "box.ply": mesh.export(file_type="ply", encoding="binary"),
        "box.stl": mesh.export(file_type="stl"),
        "box.glb": write_glb(workdir / "original.glb", document, blob).read_bytes(),
        "textured.glb": write_glb(workdir / "textured_original.glb", *textured_square()).read_bytes(),
    }


@fuzz_settings(BINARY_EXAMPLES)
@given(
    name=st.sampled_from(["box.glb", "textured.glb", "box.ply", "box.stl"]),
    cut=st.floats(0.0, 1.0),
    flips=st.lists(st.tuples(st.floats(0.0, 1.0, exclude_max=True), st.integers(0, 255)), max_size=6),
)
def test_truncated_and_garbled_binary_files(workdir, originals, name, cut, flips):
    data = bytearray(originals[name])
    for where, value in flips:
        data[int(where * len(data))] = value
    data = data[: int(cut * len(data))] if cut < 1.0 else data
    (workdir / name).write_bytes(bytes(data))
    outcome(workdir / name)


json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-(2**70), 2**70)
    | st.sampled_from([10**400, -(10**400)])
    | st.floats()
    | st.text(max_size=5),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=5), children, max_size=4),
    max_leaves=8,
)


# the parts of a textured document the textured fuzz test mutates (the rest: the test above)
TEXTURED_KEYS = {"materials", "textures", "samplers", "images", "accessors", "meshes"}


def json_paths(value, prefix=()):
    """Every path into a JSON document, containers and leaves."""
    yield prefix
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, child in items:
        yield from json_paths(child, (*prefix, key))


def holds(container, key) -> bool:
    if isinstance(container, dict):
        return key in container
    return isinstance(container, list) and isinstance(key, int) and key < len(container)


def replace_at(document: dict, path: tuple, value) -> None:
    """Put `value` at `path`, unless an earlier replacement took the path away."""
    parent = document
    for key in path[:-1]:
        if not holds(parent, key):
            return
        parent = parent[key]
    if holds(parent, path[-1]):
        parent[path[-1]] = value


@fuzz_settings(JSON_EXAMPLES)
@given(data=st.data())
def test_gltf_json_with_random_values_in_random_places(workdir, data):
    document, blob = lit_boxes()
    paths = list(json_paths(document))[1:]
    for _ in range(data.draw(st.integers(1, 3))):
        replace_at(document, data.draw(st.sampled_from(paths)), data.draw(json_values))
    outcome(write_glb(workdir / "mutated.glb", document, blob), names_json_path=True)


@fuzz_settings(TEXTURED_JSON_EXAMPLES)
@given(data=st.data(), how=st.sampled_from(["bufferView", "data"]))
def test_textured_gltf_json_with_random_values_in_random_places(workdir, data, how):
    document, blob = textured_square(how)
    paths = [path for path in list(json_paths(document))[1:] if path[0] in TEXTURED_KEYS]
    for _ in range(data.draw(st.integers(1, 3))):
        replace_at(document, data.draw(st.sampled_from(paths)), data.draw(json_values))
    outcome(write_glb(workdir / "mutated_textured.glb", document, blob), names_json_path=True)


@fuzz_settings(CAMERA_JSON_EXAMPLES)
@given(data=st.data(), choice=st.none() | st.integers(-1, 3) | st.sampled_from(["front", "top", "1", ""]))
def test_gltf_cameras_with_random_values_in_random_places(workdir, data, choice):
    """The cameras and the nodes placing them mutated; one of them chosen by name or index is one of
    the scene's cameras, or a SceneLoadError naming the file."""
    document, blob = lit_boxes()
    placing = {index for index, node in enumerate(document["nodes"]) if "camera" in node}
    paths = [
        path
        for path in list(json_paths(document))[1:]
        if path[0] == "cameras" or path[0] == "nodes" and len(path) > 1 and path[1] in placing
    ]
    for _ in range(data.draw(st.integers(1, 3))):
        replace_at(document, data.draw(st.sampled_from(paths)), data.draw(json_values))
    path = write_glb(workdir / "mutated_cameras.glb", document, blob)
    scene = outcome(path, names_json_path=True)
    if isinstance(scene, Scene) and choice is not None:
        with time_limit(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                chosen = load_scene(path, camera=choice).camera.description()
            except SceneLoadError as error:
                assert str(error).startswith(f"{path}: "), error
            else:
                assert chosen in [camera.description() for _, camera in scene.cameras]


# the parts of a meshopt-compressed document the meshopt fuzz test mutates
MESHOPT_KEYS = {"bufferViews", "buffers", "accessors"}


@pytest.fixture(scope="module")
def meshopt_boxes() -> tuple[dict, bytes]:
    """The lit boxes with every view compressed by KHR_meshopt_compression: the document and its binary chunk."""
    pytest.importorskip("meshopt")
    return meshopt_compressed(*lit_boxes(), KHR)


@fuzz_settings(MESHOPT_EXAMPLES)
@given(data=st.data())
def test_meshopt_gltf_json_with_random_values_in_random_places(workdir, meshopt_boxes, data):
    document, blob = json.loads(json.dumps(meshopt_boxes[0])), meshopt_boxes[1]
    paths = [path for path in list(json_paths(document))[1:] if path[0] in MESHOPT_KEYS]
    for _ in range(data.draw(st.integers(1, 3))):
        replace_at(document, data.draw(st.sampled_from(paths)), data.draw(json_values))
    outcome(write_glb(workdir / "mutated_meshopt.glb", document, blob), names_json_path=True)


@fuzz_settings(MESHOPT_EXAMPLES)
@given(flips=st.lists(st.tuples(st.floats(0.0, 1.0, exclude_max=True), st.integers(0, 255)), min_size=1, max_size=6))
def test_garbled_meshopt_streams(workdir, meshopt_boxes, flips):
    document, blob = meshopt_boxes
    data = bytearray(blob)
    for where, value in flips:
        data[int(where * len(data))] = value
    outcome(write_glb(workdir / "garbled_meshopt.glb", document, bytes(data)))


# Values at and past the limits of glTF's numeric fields, drawn far more often than random JSON
# draws them, and a few of the wrong JSON type (None: the field removed).
edge_numbers = st.sampled_from([0, -0.0, 5e-324, 1e-45, 0.5, 1, -1, 3.14159265, 3.2, 1e308, 2**31, 2**64]) | st.floats()
field_values = edge_numbers | st.sampled_from([None, True, "1", [], {}])
CAMERA_FIELDS = {
    "perspective": ("yfov", "aspectRatio", "znear", "zfar"),
    "orthographic": ("xmag", "ymag", "znear", "zfar"),
}


def set_field(block: dict, field: str, value) -> None:
    if value is None:
        block.pop(field, None)
    else:
        block[field] = value


@fuzz_settings(FIELD_EXAMPLES)
@given(data=st.data())
def test_gltf_camera_fields_at_their_limits(workdir, data):
    """Zero, negative, subnormal, huge and non-numeric yfov, aspectRatio, xmag, ymag, znear, zfar."""
    document, blob = lit_boxes()
    for _ in range(data.draw(st.integers(1, 3))):
        camera = data.draw(st.sampled_from(document["cameras"]))
        kind = camera["type"]
        set_field(camera[kind], data.draw(st.sampled_from(CAMERA_FIELDS[kind])), data.draw(field_values))
    outcome(write_glb(workdir / "camera_fields.glb", document, blob), names_json_path=True)


MESHOPT_FIELDS = {
    "filter": st.sampled_from(["NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL", "COLOR", "SMOOTH", "", 0]),
    "mode": st.sampled_from(["ATTRIBUTES", "TRIANGLES", "INDICES", "VERTICES", "", 4]),
    "byteStride": st.sampled_from([0, 1, 2, 3, 4, 6, 8, 12, 16, 256, 260, -4]),
    "count": st.integers(-1, 80) | st.sampled_from([2**32, 3 * 2**60]),
    "buffer": st.integers(-1, 2),
}


@fuzz_settings(FIELD_EXAMPLES)
@given(data=st.data())
def test_meshopt_blocks_with_wrong_filters_modes_strides_and_truncated_streams(workdir, meshopt_boxes, data):
    """Each compressed view's block given a filter, mode, stride or count it may not have, or its
    stream cut short (byteLength) or moved (byteOffset) within the compressed bytes."""
    document, blob = json.loads(json.dumps(meshopt_boxes[0])), meshopt_boxes[1]
    blocks = [view["extensions"][KHR] for view in document["bufferViews"] if KHR in view.get("extensions", {})]
    for _ in range(data.draw(st.integers(1, 3))):
        block = data.draw(st.sampled_from(blocks))
        field = data.draw(st.sampled_from([*MESHOPT_FIELDS, "byteLength", "byteOffset"]))
        if field in MESHOPT_FIELDS:
            set_field(block, field, data.draw(MESHOPT_FIELDS[field] | st.none()))
        else:  # a truncated or shifted stream
            extent = block.get("byteOffset", 0) + block["byteLength"]
            set_field(block, field, int(data.draw(st.floats(0, 1)) * extent))
    outcome(write_glb(workdir / "meshopt_fields.glb", document, blob), names_json_path=True)


@fuzz_settings(FIELD_EXAMPLES)
@given(data=st.data())
def test_color_0_accessors_of_wrong_types_counts_and_values(workdir, data):
    """The first box's COLOR_0 accessor given another componentType, type, normalized flag, count or
    byteOffset, its attribute another index, or its stored floats replaced by any float32."""
    document, blob = lit_boxes()
    attributes = document["meshes"][0]["primitives"][0]["attributes"]
    accessor = document["accessors"][attributes["COLOR_0"]]
    values = {
        "componentType": st.sampled_from([5120, 5121, 5122, 5123, 5124, 5125, 5126, 0]),
        "type": st.sampled_from(["SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT4", "vec4"]),
        "normalized": st.sampled_from([True, False, 1]),
        "count": st.sampled_from([0, 1, accessor["count"] - 1, accessor["count"] + 1, -1, 2**40]),
        "byteOffset": st.sampled_from([1, 2, 4, 16, -4, 10**6]),
    }
    for _ in range(data.draw(st.integers(1, 3))):
        field = data.draw(st.sampled_from([*values, "COLOR_0", "data"]))
        if field == "COLOR_0":
            attributes["COLOR_0"] = data.draw(st.sampled_from([-1, len(document["accessors"]), 0.5, "0"]))
        elif field == "data":
            view = document["bufferViews"][accessor["bufferView"]]
            floats = data.draw(st.lists(st.floats(width=32), min_size=1, max_size=8))
            start = view["byteOffset"] + 4 * data.draw(st.integers(0, view["byteLength"] // 4 - len(floats)))
            blob = blob[:start] + np.array(floats, "<f4").tobytes() + blob[start + 4 * len(floats) :]
        else:
            set_field(accessor, field, data.draw(values[field] | st.none()))
    outcome(write_glb(workdir / "color_fields.glb", document, blob), names_json_path=True)


@pytest.fixture(scope="module")
def ktx2_square() -> tuple[dict, bytes, int]:
    """The textured square with its one image a UASTC KTX2: document, buffer and the image's view."""
    pytest.importorskip("opengl_basisu")
    pytest.importorskip("alktx2")
    document, blob = ktx2_textured_square(encode_ktx2(marked_pixels(16), "uastc", srgb=True))
    return document, blob, document["images"][0]["bufferView"]


@fuzz_settings(FIELD_EXAMPLES)
@given(
    cut=st.floats(0.0, 1.0),
    flips=st.lists(st.tuples(st.floats(0.0, 1.0, exclude_max=True), st.integers(0, 255)), max_size=6),
)
def test_truncated_and_garbled_ktx2_textures(workdir, ktx2_square, cut, flips):
    document, blob, view_index = ktx2_square
    document = json.loads(json.dumps(document))
    view = document["bufferViews"][view_index]
    data = bytearray(blob[view["byteOffset"] : view["byteOffset"] + view["byteLength"]])
    for where, value in flips:
        data[int(where * len(data))] = value
    view["byteLength"] = int(cut * len(data)) if cut < 1.0 else len(data)
    blob = blob[: view["byteOffset"]] + bytes(data) + blob[view["byteOffset"] + len(data) :]
    outcome(write_glb(workdir / "garbled_ktx2.glb", document, blob), names_json_path=True)
