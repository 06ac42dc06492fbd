"""Vertex colours from files: glTF's COLOR_0 of every type the specification allows (float, or
normalized unsigned bytes and shorts; VEC3 or VEC4) becomes the shape's linear RGBA corner colours,
other types and values outside [0, 1] a one-line SceneLoadError naming the file and the attribute's
JSON path, COLOR_1 and above one warning per file; OBJ's `v x y z r g b` (sRGB-encoded) becomes
linear colours, a `v` line of another length an error naming file and line."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from wgputrace import SceneLoadError, SceneLoadWarning, load_scene
from wgputrace.scene.texture import srgb_to_linear
from wgputrace.testing.gltf_files import (
    ACCESSOR_TYPES,
    SQUARE,
    SQUARE_INDICES,
    add_view,
    gltf_document,
    with_vertex_attribute,
    write_glb,
)

FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT, SHORT = 5126, 5121, 5123, 5122
NUMPY_TYPES = {FLOAT: "<f4", UNSIGNED_BYTE: "<u1", UNSIGNED_SHORT: "<u2", SHORT: "<i2"}
COLOR_PATH = "meshes[0].primitives[0].attributes.COLOR_0"
# one RGBA colour per corner of SQUARE, each channel a different value in [0, 1]
SQUARE_COLORS = np.array([[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 0.5], [0.0, 0.0, 1.0, 0.25], [0.2, 0.4, 0.6, 0.0]])


def with_colors(rows: np.ndarray, component: int, normalized: bool | None, width: int = 4) -> tuple[dict, bytes]:
    """The square with COLOR_0 of `rows` (its first `width` channels) stored as `component`, its
    accessor's `normalized` set unless None."""
    document, blob = gltf_document([(SQUARE, SQUARE_INDICES, None)])
    values = np.ascontiguousarray(rows[:, :width], NUMPY_TYPES[component])
    view, blob = add_view(document, blob, values.tobytes())
    accessor = {"bufferView": view, "componentType": component, "count": len(values), "type": ACCESSOR_TYPES[width]}
    if normalized is not None:
        accessor["normalized"] = normalized
    document["accessors"].append(accessor)
    document["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = len(document["accessors"]) - 1
    return document, blob


def corner_colors(rows: np.ndarray) -> np.ndarray:
    """Per-vertex RGBA `rows` at the corners of SQUARE_INDICES."""
    return rows[SQUARE_INDICES].astype(np.float32)


@pytest.mark.parametrize(
    "component, scale, width",
    [(FLOAT, 1, 4), (FLOAT, 1, 3), (UNSIGNED_BYTE, 255, 4), (UNSIGNED_BYTE, 255, 3), (UNSIGNED_SHORT, 65535, 4)],
    ids=[
        "float VEC4",
        "float VEC3",
        "normalized UNSIGNED_BYTE VEC4",
        "normalized UNSIGNED_BYTE VEC3",
        "UNSIGNED_SHORT",
    ],
)
def test_gltf_color_0_of_each_accepted_type_becomes_corner_colours(tmp_path, component, scale, width):
    stored = np.round(SQUARE_COLORS * scale)
    document, blob = with_colors(stored, component, normalized=None if component == FLOAT else True, width=width)
    (shape,) = load_scene(write_glb(tmp_path / "colored.glb", document, blob)).shapes
    expected = stored / scale
    expected[:, width:] = 1.0  # VEC3: alpha 1
    np.testing.assert_allclose(shape.colors, corner_colors(expected), rtol=0, atol=1e-7)


def test_gltf_without_color_0_has_no_colours(tmp_path):
    document, blob = gltf_document([(SQUARE, SQUARE_INDICES, None)])
    (shape,) = load_scene(write_glb(tmp_path / "plain.glb", document, blob)).shapes
    assert shape.colors is None


@pytest.mark.parametrize(
    "component, normalized, width, rows, message",
    [
        (
            FLOAT,
            None,
            1,
            SQUARE_COLORS,
            r"must be \('VEC3', 'VEC4'\) of componentType \(5126, 5121, 5123\), got SCALAR",
        ),
        (FLOAT, None, 2, SQUARE_COLORS, "got VEC2 of 5126"),
        (SHORT, True, 4, SQUARE_COLORS * 100, "got VEC4 of 5122"),
        (UNSIGNED_BYTE, None, 4, SQUARE_COLORS * 255, "uint8 colours must be normalized"),
        (UNSIGNED_SHORT, False, 3, SQUARE_COLORS * 255, "uint16 colours must be normalized"),
        (FLOAT, None, 4, SQUARE_COLORS * 2, r"colour \[2.0, 0.0, 0.0, 2.0\] of vertex 0 is not in \[0, 1\]"),
        (FLOAT, None, 3, np.full((4, 4), np.nan), r"colour \[nan, nan, nan\] of vertex 0 is not in \[0, 1\]"),
    ],
    ids=["SCALAR", "VEC2", "SHORT", "UNSIGNED_BYTE unnormalized", "UNSIGNED_SHORT normalized false", "above 1", "NaN"],
)
def test_gltf_color_0_of_a_wrong_type_is_a_one_line_error_naming_its_json_path(
    tmp_path, component, normalized, width, rows, message
):
    document, blob = with_colors(rows, component, normalized, width)
    path = write_glb(tmp_path / "bad.glb", document, blob)
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(path)
    text = str(caught.value)
    assert text.startswith(f"{path}: {COLOR_PATH}") and "\n" not in text


def test_gltf_color_0_of_another_length_than_the_positions_is_an_error(tmp_path):
    document, blob = gltf_document([(SQUARE, SQUARE_INDICES, None)])
    blob = with_vertex_attribute(document, blob, 0, "COLOR_0", SQUARE_COLORS[:3])
    with pytest.raises(SceneLoadError, match=re.escape(f"{COLOR_PATH}: has 3 values for 4 positions")):
        load_scene(write_glb(tmp_path / "short.glb", document, blob))


def test_gltf_colours_beyond_color_0_are_named_in_one_warning_per_file(tmp_path):
    document, blob = gltf_document([(SQUARE, SQUARE_INDICES, None), (SQUARE + 2, SQUARE_INDICES, None)])
    for mesh in (0, 1):
        for semantic in ("COLOR_0", "COLOR_1"):
            blob = with_vertex_attribute(document, blob, mesh, semantic, SQUARE_COLORS)
    blob = with_vertex_attribute(document, blob, 1, "COLOR_2", SQUARE_COLORS[:, :3])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = load_scene(write_glb(tmp_path / "layers.glb", document, blob))
    unread = [w for w in caught if issubclass(w.category, SceneLoadWarning) and "COLOR_" in str(w.message)]
    assert [str(w.message) for w in unread] == [
        f"{tmp_path / 'layers.glb'}: vertex colours COLOR_1, COLOR_2 not read (only COLOR_0 is): ignored"
    ]
    for shape in scene.shapes:  # COLOR_0 is what they carry
        np.testing.assert_array_equal(shape.colors, corner_colors(SQUARE_COLORS))


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_obj_vertex_colours_are_srgb_decoded_and_white_where_a_vertex_has_none(tmp_path):
    text = "v 0 0 0 1 0 0.5\nv 1 0 0 0 1 0\nv 0 1 0\nv 1 1 0 1.0\nf 1 2 3\nf 2 4 3\n"
    (shape,) = load_scene(write(tmp_path / "colored.obj", text)).shapes
    linear = np.ones((4, 4))
    linear[:2, :3] = srgb_to_linear(np.array([[1, 0, 0.5], [0, 1, 0]]))
    np.testing.assert_allclose(shape.colors, linear[[[0, 1, 2], [1, 3, 2]]], rtol=1e-6)
    assert 0.2 < shape.colors[0, 0, 2] < 0.22  # sRGB 0.5 is linear 0.214


def test_obj_without_vertex_colours_has_none(tmp_path):
    (shape,) = load_scene(write(tmp_path / "plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0 1\nf 1 2 3\n")).shapes
    assert shape.colors is None


@pytest.mark.parametrize(
    "line, message",
    [
        ("v 0 1 0 1 0", "a vertex is x y z, x y z w or x y z r g b, got 5 numbers: 'v 0 1 0 1 0'"),
        ("v 0 1 0 1 0 0 1", "got 7 numbers"),
        ("v 0 1 0 1 x 0", "vertex colours must be numbers, got '1 x 0'"),
        ("v 0 1 0 255 0 0", r"vertex colours must be in \[0, 1\], got '255 0 0'"),
        ("v 0 1 0 0.5 nan 0", "vertex colours must be finite"),
    ],
)
def test_obj_bad_vertex_colours_name_file_and_line(tmp_path, line, message):
    path = write(tmp_path / "bad.obj", f"v 0 0 0\nv 1 0 0\n{line}\nf 1 2 3\n")
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(path)
    assert caught.value.line == 3 and str(caught.value).startswith(f"{path}:3: ")
