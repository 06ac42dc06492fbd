"""meshopt-compressed glTF (EXT_meshopt_compression, KHR_meshopt_compression): files compressed here
with the meshopt package's encoder load to the same triangles as the uncompressed file, in every
mode, each filter within its quantisation; the fallback buffer is read only where there is no
decoder; broken extension blocks are one-line SceneLoadErrors naming the file and JSON path."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from wgputrace import SceneLoadError, load_scene
from wgputrace.loaders.errors import SceneLoadWarning
from wgputrace.loaders.gltf import _Reader
from wgputrace.testing.gltf_files import (
    BOX,
    BOX_INDICES,
    MATERIALS,
    add_view,
    gltf_document,
    with_vertex_attribute,
    write_glb,
)
from wgputrace.testing.meshopt_files import EXT, KHR, meshopt_glb

meshopt = pytest.importorskip("meshopt")

FLOAT, SHORT, UNSIGNED_SHORT = 5126, 5122, 5123
SEED = 25
VECTORS = 64
# Bits each filter keeps per component in these tests, and the error bound they give on a value in
# [-1, 1]: half a step of the quantisation, plus the 16-bit storage's own half step.
FILTER_BITS = 12
FILTER_TOLERANCE = 2.0 ** -(FILTER_BITS - 1) + 2.0**-15
# Signed mantissa bits of the EXPONENTIAL filter: each component keeps 14 bits of magnitude below its
# own power of two, so it is off by at most half a step, 2^-14 of its value.
EXPONENT_BITS = 15
# An octahedral code's z is 1 - |x| - |y| (two steps of error) before the vector, at least 1/sqrt(3)
# long, is normalised: up to 2 sqrt(3) times the error of one component on the unit sphere.
OCTAHEDRAL_TOLERANCE = 2 * np.sqrt(3) * FILTER_TOLERANCE


def box_normals() -> np.ndarray:
    corners = BOX[BOX_INDICES]
    faces = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return np.repeat(faces / np.linalg.norm(faces, axis=1, keepdims=True), 3, axis=0).astype(np.float32)


def box_document() -> tuple[dict, bytes]:
    """The unit box with NORMAL, one diffuse material: views 0 positions, 1 indices, 2 normals."""
    document, blob = gltf_document([(BOX, BOX_INDICES, 0)], materials=MATERIALS[:1])
    return document, with_vertex_attribute(document, blob, 0, "NORMAL", box_normals())


def rewritten(path, change) -> None:
    """The GLB at `path` rewritten after `change(document)` edits its JSON."""
    reader = _Reader(path)
    change(reader.document)
    write_glb(path, reader.document, reader.binary_chunk)


def load_error(path) -> str:
    with pytest.raises(SceneLoadError) as caught:
        load_scene(path)
    message = str(caught.value)
    assert message.startswith(str(path)) and "\n" not in message, message
    return message


@pytest.mark.parametrize("extension", [EXT, KHR])
@pytest.mark.parametrize("index_mode", ["TRIANGLES", "INDICES"])
def test_a_compressed_box_loads_the_same_triangles_and_normals(tmp_path, extension, index_mode):
    document, blob = box_document()
    plain = load_scene(write_glb(tmp_path / "plain.glb", document, blob)).shapes[0]
    path = meshopt_glb(tmp_path / "packed.glb", document, blob, extension, index_mode=index_mode)
    assert extension in _Reader(path).document["extensionsRequired"]
    (shape,) = load_scene(path).shapes
    np.testing.assert_array_equal(shape.vertices, plain.vertices)
    np.testing.assert_array_equal(shape.normals, plain.normals)


def test_exponential_positions_load_within_their_mantissa(tmp_path):
    document, blob = box_document()
    rng = np.random.default_rng(SEED)
    positions = (BOX + rng.uniform(-0.1, 0.1, BOX.shape)).astype(np.float32)
    blob = positions.tobytes() + blob[positions.nbytes :]  # view 0 holds the positions
    rows = meshopt.encode_filter_exp(positions, EXPONENT_BITS, "Separate")
    path = meshopt_glb(tmp_path / "exp.glb", document, blob, filtered={0: ("EXPONENTIAL", rows)})
    (shape,) = load_scene(path).shapes
    np.testing.assert_allclose(
        shape.vertices.reshape(-1, 3), positions[BOX_INDICES].reshape(-1, 3), rtol=2.0 ** -(EXPONENT_BITS - 1)
    )


def unit_vectors(rng, count: int) -> np.ndarray:
    vectors = rng.normal(size=(count, 4))
    return (vectors / np.linalg.norm(vectors, axis=1, keepdims=True)).astype(np.float32)


def filtered_accessor(tmp_path, extension: str, filter_: str, values: np.ndarray, component: int):
    """The box file with one more accessor (index 3, VEC4 of 16-bit normalized `component`), its
    view compressed with `filter_` from float `values`; what the loader reads of it, as floats."""
    encode = {
        "OCTAHEDRAL": lambda: meshopt.encode_filter_oct(values, 8, FILTER_BITS),
        "QUATERNION": lambda: meshopt.encode_filter_quat(values, 8, FILTER_BITS),
        "COLOR": lambda: meshopt.encode_filter_color(values, 8, FILTER_BITS),
    }[filter_]
    document, blob = box_document()
    view, blob = add_view(document, blob, bytes(8 * len(values)))
    document["accessors"].append(
        {"bufferView": view, "componentType": component, "normalized": True, "count": len(values), "type": "VEC4"}
    )
    path = meshopt_glb(tmp_path / "filtered.glb", document, blob, extension, filtered={view: (filter_, encode())})
    data = _Reader(path).accessor(3, "accessors[3]", (component,), ("VEC4",))
    return data / np.float64(np.iinfo(data.dtype).max)


@pytest.mark.parametrize("extension", [EXT, KHR])
def test_octahedral_normals_decode_to_unit_vectors_within_the_filters_bits(tmp_path, extension):
    normals = unit_vectors(np.random.default_rng(SEED), VECTORS)
    normals[:, 3] = 1.0  # the filter keeps w as is (a tangent's sign)
    normals[:, :3] /= np.linalg.norm(normals[:, :3], axis=1, keepdims=True)
    decoded = filtered_accessor(tmp_path, extension, "OCTAHEDRAL", normals, SHORT)
    np.testing.assert_allclose(decoded[:, :3], normals[:, :3], atol=OCTAHEDRAL_TOLERANCE)
    np.testing.assert_array_equal(decoded[:, 3], 1.0)


@pytest.mark.parametrize("extension", [EXT, KHR])
def test_quaternions_decode_within_the_filters_bits(tmp_path, extension):
    quaternions = unit_vectors(np.random.default_rng(SEED), VECTORS)
    quaternions *= np.sign(quaternions[:, 3:])  # q and -q are one rotation: compare with w >= 0
    decoded = filtered_accessor(tmp_path, extension, "QUATERNION", quaternions, SHORT)
    decoded *= np.sign(decoded[:, 3:])
    np.testing.assert_allclose(decoded, quaternions, atol=FILTER_TOLERANCE)


def test_colors_decode_within_the_filters_bits(tmp_path):
    colors = np.random.default_rng(SEED).uniform(0, 1, (VECTORS, 4)).astype(np.float32)
    decoded = filtered_accessor(tmp_path, KHR, "COLOR", colors, UNSIGNED_SHORT)
    # YCoCg with FILTER_BITS bits each: the round trip through three components costs up to two steps
    np.testing.assert_allclose(decoded, colors, atol=2 * FILTER_TOLERANCE)


def without_meshopt(monkeypatch):
    monkeypatch.setitem(sys.modules, "meshopt", None)  # `import meshopt` then raises ImportError


def test_a_file_requiring_meshopt_without_the_package_says_how_to_install_it(tmp_path, monkeypatch):
    path = meshopt_glb(tmp_path / "packed.glb", *box_document())
    without_meshopt(monkeypatch)
    message = load_error(path)
    assert (
        f"extensionsRequired: not supported here: {EXT} (meshoptimizer-compressed buffers): needs meshopt: " in message
    )
    assert "pip install meshopt" in message


def test_a_file_only_using_meshopt_loads_its_fallback_without_the_package(tmp_path, monkeypatch):
    document, blob = box_document()
    plain = load_scene(write_glb(tmp_path / "plain.glb", document, blob)).shapes[0]
    path = meshopt_glb(tmp_path / "packed.glb", document, blob, fallback_data=True)
    rewritten(path, lambda d: d["bufferViews"][0]["extensions"][EXT].update(byteLength=4))
    assert "do not decode" in load_error(path)  # with the package, the (now cut) compressed bytes are read
    without_meshopt(monkeypatch)
    with pytest.warns(SceneLoadWarning, match=rf"{EXT} \(meshoptimizer-compressed buffers\) not supported"):
        (shape,) = load_scene(path).shapes
    np.testing.assert_array_equal(shape.vertices, plain.vertices)


def test_a_fallback_buffer_without_a_uri_holds_no_data(tmp_path):
    path = meshopt_glb(tmp_path / "packed.glb", *box_document())
    rewritten(path, lambda d: d["bufferViews"][0].pop("extensions"))
    assert "bufferViews[0]: reads buffers[1], a EXT_meshopt_compression fallback without a uri: it holds no data" in (
        load_error(path)
    )


def broken(tmp_path, change, view: int = 0, extension: str = EXT) -> str:
    """The load error of the compressed box after `change(block)` edits bufferView `view`'s block."""
    path = meshopt_glb(tmp_path / "packed.glb", *box_document(), extension)
    rewritten(path, lambda d: change(d["bufferViews"][view]["extensions"][extension]))
    return load_error(path)


def test_a_truncated_stream_names_its_view(tmp_path):
    message = broken(tmp_path, lambda block: block.update(byteLength=block["byteLength"] // 2))
    assert (
        f"bufferViews[0].extensions.{EXT}: its " in message
        and f"do not decode to {len(BOX)} elements of 12 bytes" in message
    )


@pytest.mark.parametrize(
    "change, view, where, said",
    [
        (lambda b: b.update(mode="VERTICES"), 0, "mode", "must be one of ATTRIBUTES, TRIANGLES, INDICES"),
        (lambda b: b.update(filter="SMOOTH"), 0, "filter", "must be one of NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL"),
        (lambda b: b.update(filter="COLOR"), 0, "filter", "got 'COLOR'"),  # KHR_ only
        (lambda b: b.update(filter="OCTAHEDRAL"), 2, "byteStride", "must be 4 or 8 with filter OCTAHEDRAL, got 12"),
        (lambda b: b.update(filter="EXPONENTIAL"), 1, "filter", "must be NONE in mode TRIANGLES"),
        (lambda b: b.update(byteStride=6), 0, "byteStride", "must be a multiple of 4 from 4 to 256"),
        (lambda b: b.update(byteStride=8), 1, "byteStride", "must be 2 or 4 in mode TRIANGLES, got 8"),
        (lambda b: b.update(count=35), 1, "count", "must be a multiple of 3 in mode TRIANGLES"),
        (
            lambda b: b.update(count=20),
            0,
            "",
            "byteStride 12 x count 20 = 240 bytes, but bufferViews[0] has byteLength",
        ),
        (lambda b: b.pop("mode"), 0, "", "'mode' is missing"),
        (lambda b: b.update(buffer=1), 0, "", "reads buffers[1], a EXT_meshopt_compression fallback without a uri"),
        (lambda b: b.update(byteOffset=10**6), 0, "", "lie beyond the buffer"),
        (
            lambda b: b.update(count=3 * 2**60, byteLength=1),
            1,
            "",
            "1 compressed bytes cannot hold 13835058055282163712",
        ),
    ],
)
def test_a_broken_extension_block_names_its_field(tmp_path, change, view, where, said):
    message = broken(tmp_path, change, view)
    path = f"bufferViews[{view}].extensions.{EXT}" + (f".{where}" if where else "")
    assert f"{path}: " in message and said in message, message


def test_a_view_stride_unlike_the_extensions_is_refused(tmp_path):
    path = meshopt_glb(tmp_path / "packed.glb", *box_document())
    rewritten(path, lambda d: d["bufferViews"][0].update(byteStride=16))  # the positions are 12 bytes apart
    message = load_error(path)
    assert f"bufferViews[0].extensions.{EXT}: byteStride 12 differs from bufferViews[0].byteStride 16" in message


def test_an_uncompressed_view_beside_compressed_ones_reads_its_own_bytes(tmp_path):
    document, blob = box_document()
    view, blob = add_view(document, blob, b"\x89PNG image bytes")  # no accessor reads it: left uncompressed
    reader = _Reader(meshopt_glb(tmp_path / "packed.glb", document, blob))
    assert "extensions" not in reader.document["bufferViews"][view]
    assert bytes(reader.view(view, "images[0].bufferView")[0]) == b"\x89PNG image bytes"
