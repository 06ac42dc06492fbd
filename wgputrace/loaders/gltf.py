"""glTF 2.0 (.gltf with its buffers, or binary .glb): triangles, node transforms, materials
(`GltfMaterials`), cameras (`node_camera`) and punctual lights; errors name the file and the JSON path.

Not trimesh's glTF reader: its PBRMaterial drops keys it does not know (KHR_materials_transmission,
KHR_materials_ior) and it ignores cameras without the optional aspectRatio. Each mesh instance in
the default scene's node tree becomes one Shape per triangle primitive, the node's world matrix its
`transform` (a mesh that several nodes share: one Shape per primitive placed by an Instance per node,
`placed_meshes`), NORMAL its corner normals (none: flat, as glTF asks), TEXCOORD_0 and TANGENT where its
material's textures or anisotropy need them (else MikkTSpace's tangents), integer ones (KHR_mesh_quantization)
dequantised by `vertex_attribute`, COLOR_0 its vertex colours (`vertex_colors`). Sparse accessors,
skins, morph targets, TEXCOORD_1 and COLOR_1 and above are not read. A required extension outside
READ_EXTENSIONS (and Draco's where DracoPy imports; meshopt's where the meshopt package does,
`gltf_meshopt`; KTX2 textures' where opengl-basisu does, `ktx2_images`) is refused by name; one
that is only used is ignored with a warning.
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import struct
import warnings
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..scene import (
    DirectionalLight,
    Light,
    LightError,
    PointLight,
    SceneError,
    Sensor,
    Shape,
    SpotLight,
)
from ..scene.instances import Instance
from .errors import SceneLoadError, SceneLoadWarning
from .gltf_anisotropy import ANISOTROPY
from .gltf_cameras import node_camera
from .gltf_colors import vertex_colors, warn_unread_colors
from .gltf_compression import (
    DRACO_EXTENSION,
    DRACO_INSTALL_HINT,
    DracoDecodeError,
    DracoMesh,
    DracoMissing,
    decode_draco,
    draco_available,
)
from .gltf_instances import placed_meshes
from .gltf_material_lobes import LOBE_EXTENSIONS, UNMAPPED_MATERIAL_EXTENSIONS
from .gltf_materials import TRANSFORM_EXTENSION, GltfMaterials
from .gltf_meshopt import (
    MESHOPT_EXTENSIONS,
    MESHOPT_INSTALL_HINT,
    MeshoptDecodeError,
    MeshoptMissing,
    compressed_view,
    decode_view,
    is_fallback,
    meshopt_available,
    meshopt_extension,
)
from .gltf_quantization import QUANTIZATION_EXTENSION, vertex_attribute
from .gltf_specular_glossiness import SPECULAR_GLOSSINESS
from .gltf_volume import VOLUME_EXTENSION
from .ktx2_images import BASISU_EXTENSION, KTX2_INSTALL_HINT, ktx2_available

GLB_MAGIC = 0x46546C67  # "glTF"
GLB_JSON_CHUNK = 0x4E4F534A
GLB_BIN_CHUNK = 0x004E4942
# componentType -> numpy dtype (little-endian, as glTF stores everything)
COMPONENT_TYPES = {5120: "<i1", 5121: "<u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
INDEX_TYPES = (5121, 5123, 5125)
ELEMENT_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
MODE_TRIANGLES, MODE_STRIP, MODE_FAN = 4, 5, 6
LIGHTS_EXTENSION = "KHR_lights_punctual"
LIGHTS = f"extensions.{LIGHTS_EXTENSION}.lights"  # the JSON path of the extension's light array
# KHR_lights_punctual's defaults and limit for a spot's cones (radians)
DEFAULT_INNER_CONE, DEFAULT_OUTER_CONE, MAX_OUTER_CONE = 0.0, math.pi / 4, math.pi / 2
# The extensions whose data this module reads (Draco's, meshopt's and KTX2's only while their decoders import).
READ_EXTENSIONS = {
    LIGHTS_EXTENSION,
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    VOLUME_EXTENSION,
    TRANSFORM_EXTENSION,
    QUANTIZATION_EXTENSION,
    *LOBE_EXTENSIONS,
    ANISOTROPY,
    SPECULAR_GLOSSINESS,
}
# What the refusal of a required extension says about it: what it is, and how to get support.
UNREAD_EXTENSIONS = {
    DRACO_EXTENSION: ("Draco-compressed meshes", f"needs DracoPy: {DRACO_INSTALL_HINT}"),
    **{
        name: ("meshoptimizer-compressed buffers", f"needs meshopt: {MESHOPT_INSTALL_HINT}")
        for name in MESHOPT_EXTENSIONS
    },
    BASISU_EXTENSION: ("KTX2 textures", f"needs opengl-basisu: {KTX2_INSTALL_HINT}"),
    **UNMAPPED_MATERIAL_EXTENSIONS,
}


class _Reader:
    """One glTF file: typed access to its JSON with errors naming the JSON path, and its buffers."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.binary_chunk: bytes | None = None
        self.document = self._document()
        self._buffers: dict[int, bytes] = {}
        self._check_extensions()
        self._draco_accessors = self._draco_sources()
        self._draco_meshes: dict[int, DracoMesh] = {}
        self._decoded_views: dict[int, bytes] = {}

    def fail(self, where: str, problem: str) -> SceneLoadError:
        return SceneLoadError(self.path, f"{where}: {problem}")

    def _document(self) -> dict:
        try:
            data = self.path.read_bytes()
        except OSError as error:
            raise SceneLoadError(self.path, f"cannot read the file: {error.strerror or error}") from None
        if data[:4] == struct.pack("<I", GLB_MAGIC):
            text = self._glb_chunks(data)
        else:
            text = data
        try:
            document = json.loads(text)
        except (ValueError, RecursionError) as error:
            line = getattr(error, "lineno", None) if data[:4] != struct.pack("<I", GLB_MAGIC) else None
            raise SceneLoadError(self.path, f"the glTF JSON does not parse: {error}", line) from None
        if not isinstance(document, dict):
            raise SceneLoadError(self.path, f"the glTF JSON must be an object, got {type(document).__name__}")
        return document

    def _glb_chunks(self, data: bytes) -> bytes:
        if len(data) < 20:
            raise SceneLoadError(
                self.path, f"GLB file of {len(data)} bytes is shorter than its 12-byte header and a chunk"
            )
        _, version, length = struct.unpack_from("<III", data, 0)
        if version != 2:
            raise SceneLoadError(self.path, f"GLB version {version}; only glTF 2 is supported")
        if length > len(data):
            raise SceneLoadError(self.path, f"GLB header says {length} bytes, the file has {len(data)} (truncated?)")
        chunks, offset = [], 12
        while offset + 8 <= length:
            size, kind = struct.unpack_from("<II", data, offset)
            if offset + 8 + size > length:
                raise SceneLoadError(
                    self.path, f"GLB chunk at byte {offset} of {size} bytes runs past the end ({length})"
                )
            chunks.append((kind, data[offset + 8 : offset + 8 + size]))
            offset += 8 + size
        if not chunks or chunks[0][0] != GLB_JSON_CHUNK:
            raise SceneLoadError(self.path, "GLB's first chunk must be JSON")
        if len(chunks) > 1 and chunks[1][0] == GLB_BIN_CHUNK:
            self.binary_chunk = chunks[1][1]
        return chunks[0][1]

    def _check_extensions(self) -> None:
        """Refuse a file requiring an extension we do not read, and warn of those it only uses."""
        required = self._extension_names("extensionsRequired")
        used = self._extension_names("extensionsUsed")
        readable = (
            READ_EXTENSIONS
            | ({DRACO_EXTENSION} if draco_available() else set())
            | (set(MESHOPT_EXTENSIONS) if meshopt_available() else set())
            | ({BASISU_EXTENSION} if ktx2_available() else set())
        )
        unread = [name for name in required if name not in readable]
        if unread:
            raise self.fail(
                "extensionsRequired",
                "not supported here: " + "; ".join(_unread_extension(name, detail=True) for name in unread),
            )
        ignored = [name for name in used if name not in readable and name not in required]
        if ignored:
            warnings.warn(
                f"{self.path}: extensionsUsed: {', '.join(_unread_extension(name) for name in ignored)} "
                "not supported: ignored",
                SceneLoadWarning,
                stacklevel=5,
            )

    def _extension_names(self, key: str) -> list[str]:
        names = self.get(self.document, key, list, "glTF", [])
        if not all(isinstance(name, str) for name in names):
            raise self.fail(key, f"must be a list of extension names, got {names!r:.80}")
        return list(dict.fromkeys(names))

    def _draco_sources(self) -> dict[int, tuple[str, str, dict]]:
        """accessor index -> (JSON path of the Draco extension of the primitive using it, the
        attribute it holds there or "indices", the extension) for every accessor whose data a
        Draco primitive decodes."""
        sources: dict[int, tuple[str, str, dict]] = {}
        meshes = self.document.get("meshes")
        for mesh_index, mesh in enumerate(meshes if isinstance(meshes, list) else []):
            primitives = mesh.get("primitives") if isinstance(mesh, dict) else None
            for number, primitive in enumerate(primitives if isinstance(primitives, list) else []):
                extensions = primitive.get("extensions") if isinstance(primitive, dict) else None
                if not isinstance(extensions, dict) or DRACO_EXTENSION not in extensions:
                    continue
                where = f"meshes[{mesh_index}].primitives[{number}]"
                block = self.get(extensions, DRACO_EXTENSION, dict, f"{where}.extensions")
                accessors = self.get(primitive, "attributes", dict, where) | {"indices": primitive.get("indices")}
                where = f"{where}.extensions.{DRACO_EXTENSION}"
                for name, index in accessors.items():
                    if not isinstance(index, int) or isinstance(index, bool):
                        continue  # reading the primitive names what is wrong with it
                    if index in sources and sources[index][:2] != (where, name):
                        raise self.fail(
                            where, f"accessors[{index}] is also decoded by {sources[index][0]} as {sources[index][1]}"
                        )
                    sources[index] = (where, name, block)
        return sources

    def get(self, node: dict, key: str, kind, where: str, default=None):
        value = node.get(key, default)
        if value is None and default is None:
            raise self.fail(where, f"{key!r} is missing")
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            # JSON integers are unbounded; beyond float range they count as infinite (and fail later)
            value = float(value) if abs(value) < 2**1024 else (math.inf if value > 0 else -math.inf)
        if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
            raise self.fail(f"{where}.{key}", f"must be {getattr(kind, '__name__', kind)}, got {value!r:.60}")
        return value

    def item(self, collection: str, index, where: str) -> dict:
        """Entry `index` of the array at the dotted JSON path `collection` (`meshes`, LIGHTS)."""
        keys = collection.split(".")
        items = self.document
        for depth, key in enumerate(keys):
            last = depth == len(keys) - 1
            items = self.get(items, key, list if last else dict, ".".join(keys[:depth]) or "glTF", [] if last else {})
        if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(items):
            raise self.fail(where, f"{collection} index {index!r:.40} out of range ({len(items)} {collection})")
        value = items[index]
        if not isinstance(value, dict):
            raise self.fail(f"{collection}[{index}]", f"must be an object, got {type(value).__name__}")
        return value

    def numbers(self, node: dict, key: str, count: int, where: str, default) -> np.ndarray:
        value = node.get(key, default)
        if (
            not isinstance(value, list)
            or len(value) != count
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        ):
            raise self.fail(f"{where}.{key}", f"must be {count} numbers, got {value!r:.80}")
        try:
            array = np.array(value, dtype=np.float64)
        except OverflowError:  # a JSON integer beyond float range
            array = np.array([np.inf])
        if not np.all(np.isfinite(array)):
            raise self.fail(f"{where}.{key}", f"must be finite, got {value!r:.80}")
        return array

    def buffer(self, index: int, where: str) -> bytes:
        if index not in self._buffers:
            entry = self.item("buffers", index, where)
            uri = entry.get("uri")
            if uri is None and is_fallback(entry) and not (index == 0 and self.binary_chunk is not None):
                # meshopt's placeholder for uncompressed data the file does not carry
                hint = "" if meshopt_available() else f"; decoding the compressed views needs {MESHOPT_INSTALL_HINT}"
                raise self.fail(
                    where,
                    f"reads buffers[{index}], a {meshopt_extension(entry)} fallback without a uri: it holds no data"
                    + hint,
                )
            if uri is None:
                if self.binary_chunk is None:
                    raise self.fail(f"buffers[{index}]", "has no uri and the file has no GLB binary chunk")
                data = self.binary_chunk
            elif not isinstance(uri, str):
                raise self.fail(f"buffers[{index}].uri", f"must be a string, got {uri!r:.40}")
            elif uri.startswith("data:"):
                try:
                    data = base64.b64decode(uri.split(",", 1)[1], validate=True)
                except (IndexError, binascii.Error, ValueError) as error:
                    raise self.fail(f"buffers[{index}].uri", f"data URI does not decode: {error}") from None
            else:
                file = self.path.parent / uri
                try:
                    data = file.read_bytes()
                except OSError as error:
                    raise self.fail(f"buffers[{index}].uri", f"cannot read {file}: {error.strerror or error}") from None
            length = self.get(entry, "byteLength", int, f"buffers[{index}]")
            if length > len(data):
                raise self.fail(f"buffers[{index}]", f"byteLength {length} but only {len(data)} bytes are there")
            self._buffers[index] = data
        return self._buffers[index]

    def accessor(self, index, where: str, types: tuple[int, ...], shapes: tuple[str, ...]) -> np.ndarray:
        """Accessor `index` as a (count, components) array, every byte it reads bounds-checked."""
        where = f"{where} -> accessors[{index}]"
        entry = self.item("accessors", index, where)
        if "sparse" in entry:
            raise self.fail(where, "sparse accessors are not supported")
        component = self.get(entry, "componentType", int, where)
        shape = self.get(entry, "type", str, where)
        count = self.get(entry, "count", int, where)
        if component not in types or shape not in shapes:
            raise self.fail(where, f"must be {shapes} of componentType {types}, got {shape} of {component}")
        if count < 0:
            raise self.fail(where, f"count must be >= 0, got {count}")
        dtype = np.dtype(COMPONENT_TYPES[component])
        width = ELEMENT_SIZES[shape]
        # A Draco primitive's accessors keep a bufferView only as the fallback of a file that
        # does not require the extension; without DracoPy that fallback is read.
        if index in self._draco_accessors and ("bufferView" not in entry or draco_available()):
            return self._decoded_accessor(index, dtype, width, where)
        if "bufferView" not in entry:  # the spec says: all zeros
            return np.zeros((count, width), dtype)
        view_index = entry["bufferView"]
        view_where = f"bufferViews[{view_index}]"
        view, stride = self.view(view_index, where)
        element = dtype.itemsize * width
        stride = element if stride is None else stride
        offset = self.get(entry, "byteOffset", int, where, 0)
        if offset < 0 or stride < element:
            raise self.fail(
                where, f"negative byteOffset {offset}, or byteStride {stride} below the element size {element}"
            )
        end = offset + (stride * (count - 1) + element if count else 0)
        if end > len(view):
            raise self.fail(where, f"reads {end} bytes of {view_where}, which holds {len(view)}")
        if count == 0:
            return np.zeros((0, width), dtype)
        raw = np.frombuffer(view, np.uint8)
        rows = np.lib.stride_tricks.as_strided(raw[offset:], shape=(count, element), strides=(stride, 1))
        return np.ascontiguousarray(rows).view(dtype).reshape(count, width)

    def view(self, index, where: str) -> tuple[memoryview, int | None]:
        """The bytes of bufferView `index`, bounds-checked (decoded, for a meshopt-compressed view
        where the meshopt package imports), and its byteStride (None if unset)."""
        view = self.item("bufferViews", index, where)
        view_where = f"bufferViews[{index}]"
        stride = self.get(view, "byteStride", int, view_where) if "byteStride" in view else None
        layout = compressed_view(self, view, index) if meshopt_available() else None
        if layout is not None:
            if index not in self._decoded_views:
                data = self._bytes(layout.buffer, layout.byte_offset, layout.byte_length, layout.where)
                try:
                    self._decoded_views[index] = decode_view(layout, data)
                except (MeshoptMissing, MeshoptDecodeError) as error:
                    raise self.fail(layout.where, str(error)) from None
            return memoryview(self._decoded_views[index]), stride
        offset = self.get(view, "byteOffset", int, view_where, 0)
        length = self.get(view, "byteLength", int, view_where)
        return self._bytes(self.get(view, "buffer", int, view_where), offset, length, view_where), stride

    def _bytes(self, buffer: int, offset: int, length: int, where: str) -> memoryview:
        """`length` bytes at `offset` of buffer `buffer`, for the entry at JSON path `where`."""
        data = self.buffer(buffer, where)
        if min(offset, length) < 0:
            raise self.fail(where, f"negative byteOffset {offset} or byteLength {length}")
        if offset + length > len(data):
            raise self.fail(where, f"bytes {offset}..{offset + length} lie beyond the buffer ({len(data)} bytes)")
        return memoryview(data)[offset : offset + length]

    def _decoded_accessor(self, index: int, dtype: np.dtype, width: int, where: str) -> np.ndarray:
        """Accessor `index`'s data decoded from its Draco primitive, as `accessor` returns it."""
        draco_where, name, block = self._draco_accessors[index]
        view_index = self.get(block, "bufferView", int, draco_where)
        if view_index not in self._draco_meshes:
            data, _ = self.view(view_index, draco_where)
            try:
                self._draco_meshes[view_index] = decode_draco(data)
            except DracoMissing as error:
                raise self.fail(draco_where, str(error)) from None
            except DracoDecodeError as error:
                raise self.fail(f"{draco_where}.bufferView", str(error)) from None
        mesh = self._draco_meshes[view_index]
        if name == "indices":
            values = mesh.triangles.reshape(-1, 1)
        else:
            ids = self.get(block, "attributes", dict, draco_where)
            attribute = self.get(ids, name, int, f"{draco_where}.attributes")
            if attribute not in mesh.attributes:
                raise self.fail(
                    f"{draco_where}.attributes.{name}",
                    f"Draco attribute {attribute} is not in the decoded mesh (its ids: {sorted(mesh.attributes)})",
                )
            values = mesh.attributes[attribute]
        # The count is the decoded one: an encoder that merges equal vertices leaves fewer than
        # the accessor says, and what the indices refer to is the decoded list.
        if values.shape[1] != width:
            raise self.fail(where, f"has {width} components, its Draco data {values.shape[1]}")
        if not _holds(dtype, values):
            raise self.fail(where, f"its {dtype} cannot hold the {values.dtype} values its Draco data decodes to")
        return values.astype(dtype)


def _holds(dtype: np.dtype, values: np.ndarray) -> bool:
    """Whether `values` convert to `dtype` unchanged but for float rounding."""
    if dtype.kind == "f" or values.size == 0:
        return True
    limits = np.iinfo(dtype)
    return values.dtype.kind in "iu" and limits.min <= values.min() and values.max() <= limits.max


def _unread_extension(name: str, detail: bool = False) -> str:
    """An extension we do not read, named with what it is and, in `detail`, how to get support."""
    if name not in UNREAD_EXTENSIONS:
        return name
    what, how = UNREAD_EXTENSIONS[name]
    return f"{name} ({what}): {how}" if detail else f"{name} ({what})"


class GltfContents(NamedTuple):
    """What a glTF file holds for a Scene: its shapes, its cameras (`node_camera`), its lights."""

    shapes: list[Shape]
    cameras: list[tuple[str, Sensor]]
    lights: list[Light]
    instances: list[Instance]  # nodes sharing a mesh (`placed_meshes`)


def read_gltf(path: Path) -> GltfContents:
    reader = _Reader(path)
    document = reader.document
    scenes = reader.get(document, "scenes", list, "glTF", [])
    if scenes:
        scene_index = reader.get(document, "scene", int, "glTF", 0)
        roots = reader.get(reader.item("scenes", scene_index, "scene"), "nodes", list, f"scenes[{scene_index}]", [])
    else:  # no scenes: every node that is nobody's child is a root
        nodes = reader.get(document, "nodes", list, "glTF", [])
        children = {c for n in nodes if isinstance(n, dict) for c in n.get("children", []) if isinstance(c, int)}
        roots = [i for i in range(len(nodes)) if i not in children]
    materials = GltfMaterials(reader)
    warn_unread_colors(reader)
    placements: list[tuple[int, np.ndarray, str]] = []
    lights: list[Light] = []
    cameras: list[tuple[str, Sensor]] = []
    # (node, parent's world matrix, JSON path that reached it, its ancestors)
    stack = [(root, np.eye(4), "scene", ()) for root in reversed(roots)]
    visited: set[int] = set()
    while stack:
        index, parent, reached, ancestors = stack.pop()
        if index in ancestors:
            raise reader.fail(reached, f"is node {index}, its own ancestor: the node graph has a cycle")
        node = reader.item("nodes", index, reached)
        where = f"nodes[{index}]"
        if index in visited:
            raise reader.fail(where, "is reached twice: glTF nodes must form a tree")
        visited.add(index)
        world = parent @ _local_matrix(reader, node, where)
        if "mesh" in node:
            placements.append((reader.get(node, "mesh", int, where), world, where))
        placed = node_camera(reader, node, world, where) if "camera" in node else None
        if placed is not None:
            cameras.append(placed)
        light = _node_light(reader, node, where)
        if light is not None:
            lights.append(_light(reader, light, world, where))
        children = reader.get(node, "children", list, where, [])
        stack += [
            (child, world, f"{where}.children[{k}]", (*ancestors, index))
            for k, child in reversed(list(enumerate(children)))
        ]
    shapes, instances = placed_meshes(
        reader, placements, lambda mesh, world, where: _mesh_shapes(reader, mesh, world, materials, where)
    )
    return GltfContents(shapes, cameras, lights, instances)


def _local_matrix(reader: _Reader, node: dict, where: str) -> np.ndarray:
    if "matrix" in node:
        return reader.numbers(node, "matrix", 16, where, None).reshape(4, 4).T  # glTF is column-major
    translation = reader.numbers(node, "translation", 3, where, [0.0, 0.0, 0.0])
    x, y, z, w = reader.numbers(node, "rotation", 4, where, [0.0, 0.0, 0.0, 1.0])
    scale = reader.numbers(node, "scale", 3, where, [1.0, 1.0, 1.0])
    norm = np.sqrt(x * x + y * y + z * z + w * w)
    if norm == 0:
        raise reader.fail(f"{where}.rotation", "is the zero quaternion")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    matrix = np.eye(4)
    matrix[:3, :3] = rotation * scale
    matrix[:3, 3] = translation
    return matrix


def _mesh_shapes(reader: _Reader, mesh_index, world: np.ndarray, materials: GltfMaterials, where: str) -> list[Shape]:
    mesh = reader.item("meshes", mesh_index, f"{where}.mesh")
    mesh_where = f"meshes[{mesh_index}]"
    name = mesh.get("name") if isinstance(mesh.get("name"), str) else f"mesh{mesh_index}"
    shapes = []
    primitives = reader.get(mesh, "primitives", list, mesh_where)
    for number, primitive in enumerate(primitives):
        primitive_where = f"{mesh_where}.primitives[{number}]"
        if not isinstance(primitive, dict):
            raise reader.fail(primitive_where, f"must be an object, got {type(primitive).__name__}")
        mode = reader.get(primitive, "mode", int, primitive_where, MODE_TRIANGLES)
        if mode not in (MODE_TRIANGLES, MODE_STRIP, MODE_FAN):
            warnings.warn(
                f"{reader.path}: {primitive_where} has mode {mode} (points or lines): skipped",
                SceneLoadWarning,
                stacklevel=4,
            )
            continue
        attributes = reader.get(primitive, "attributes", dict, primitive_where)
        positions = vertex_attribute(
            reader,
            reader.get(attributes, "POSITION", int, f"{primitive_where}.attributes"),
            f"{primitive_where}.attributes.POSITION",
            "POSITION",
        )
        if "indices" in primitive:
            indices = reader.accessor(primitive["indices"], f"{primitive_where}.indices", INDEX_TYPES, ("SCALAR",))
            indices = indices.ravel().astype(np.int64)
        else:
            indices = np.arange(len(positions))
        if indices.size and indices.max() >= len(positions):
            bad = int(np.flatnonzero(indices >= len(positions))[0])
            raise reader.fail(
                f"{primitive_where}.indices",
                f"index {indices[bad]} at position {bad} is beyond the {len(positions)} positions",
            )
        faces = _triangles(indices, mode)
        if faces.size == 0:
            continue
        material = materials.material(primitive.get("material"), primitive_where)
        textures = material.textures()
        corner = {
            key: _corner_attribute(reader, attributes, semantic, faces, len(positions), primitive_where)
            for key, semantic, wanted in (
                ("normals", "NORMAL", True),
                ("uvs", "TEXCOORD_0", bool(textures) or material.reads_tangent()),
                ("tangents", "TANGENT", "normal" in textures or material.reads_tangent()),
            )
            if wanted and semantic in attributes
        }
        corner["colors"] = vertex_colors(reader, attributes, faces, len(positions), primitive_where)
        label = name if len(primitives) == 1 else f"{name}.{number}"
        try:
            shapes.append(Shape(label, positions[faces], material, transform=world, **corner))
        except SceneError as error:
            raise reader.fail(f"{where} ({primitive_where})", str(error)) from None
    return shapes


def _corner_attribute(
    reader: _Reader, attributes: dict, semantic: str, faces: np.ndarray, vertex_count: int, where: str
) -> np.ndarray:
    """(n, 3, k) float values of per-vertex attribute `semantic` at the corners of `faces`
    (`vertex_attribute`'s, integers dequantised)."""
    index = reader.get(attributes, semantic, int, f"{where}.attributes")
    where = f"{where}.attributes.{semantic}"
    values = vertex_attribute(reader, index, where, semantic)
    if len(values) != vertex_count:
        raise reader.fail(where, f"has {len(values)} values for {vertex_count} positions")
    return values[faces]


def _triangles(indices: np.ndarray, mode: int) -> np.ndarray:
    """(n, 3) vertex indices of the triangles a primitive's index list draws."""
    if mode == MODE_TRIANGLES:
        return indices[: len(indices) // 3 * 3].reshape(-1, 3)
    k = np.arange(max(len(indices) - 2, 0))
    if mode == MODE_STRIP:  # every other triangle swaps two corners to keep the winding
        odd = k % 2
        return np.stack([indices[k], indices[k + 1 + odd], indices[k + 2 - odd]], axis=1)
    return np.stack([indices[k + 1], indices[k + 2], np.broadcast_to(indices[:1], k.shape)], axis=1)


def _node_light(reader: _Reader, node: dict, where: str) -> int | None:
    """The light index a node's KHR_lights_punctual extension names, or None."""
    extensions = reader.get(node, "extensions", dict, where, {})
    if LIGHTS_EXTENSION not in extensions:
        return None
    where = f"{where}.extensions"
    return reader.get(
        reader.get(extensions, LIGHTS_EXTENSION, dict, where), "light", int, f"{where}.{LIGHTS_EXTENSION}"
    )


def _light(reader: _Reader, index: int, world: np.ndarray, where: str) -> Light:
    """Light `index` of KHR_lights_punctual placed by a node of world matrix `world`: at its
    translation, shining along its -z (as glTF's cameras look), so one light placed by two nodes is
    two lights. Units are taken 1:1 as radiometric (no 683 lm/W, as most path tracers read them):

    | glTF light                                      | wgputrace light |
    |-------------------------------------------------|-----------------|
    | `point`: intensity (candela), color             | PointLight: intensity (W/sr) = intensity, color |
    | `spot`: intensity (candela), color, `spot.innerConeAngle` (default 0), `spot.outerConeAngle` (default pi/4), radians | SpotLight: intensity on the axis, beam_width = innerConeAngle, cutoff_angle = outerConeAngle (in degrees) |
    | `directional`: intensity (lux), color           | DirectionalLight: irradiance = intensity, color |

    `range` is ignored (a real-time engines' cut-off; a physical light falls off with 1/d^2 only). A
    spot's edge is Mitsuba's (linear in angle between the cones), not glTF's (a squared ramp in cosine).
    """
    entry = reader.item(LIGHTS, index, f"{where}.extensions.{LIGHTS_EXTENSION}.light")
    light_where = f"{LIGHTS}[{index}]"
    kind = reader.get(entry, "type", str, light_where)
    color = tuple(reader.numbers(entry, "color", 3, light_where, [1.0, 1.0, 1.0]))
    intensity = reader.get(entry, "intensity", float, light_where, 1.0)
    name = entry.get("name") if isinstance(entry.get("name"), str) else f"light{index}"
    position = tuple(world[:3, 3])
    direction = tuple(world[:3, :3] @ [0.0, 0.0, -1.0])
    try:
        if kind == "point":
            return PointLight(position, intensity, color=color, name=name)
        if kind == "directional":
            return DirectionalLight(direction, intensity, color=color, name=name)
        if kind == "spot":
            inner, outer = _spot_cones(reader, entry, light_where)
            return SpotLight(
                position,
                direction,
                intensity,
                cutoff_angle_degrees=math.degrees(outer),
                beam_width_degrees=math.degrees(inner),
                color=color,
                name=name,
            )
    except LightError as error:
        raise reader.fail(f"{light_where} (placed by {where})", str(error)) from None
    raise reader.fail(f"{light_where}.type", f"must be 'point', 'spot' or 'directional', got {kind!r:.40}")


def _spot_cones(reader: _Reader, entry: dict, where: str) -> tuple[float, float]:
    """A spot light's inner and outer cone angles (radians), in glTF's range. glTF asks inner < outer,
    but exporters write them equal for a hard-edged spot (Blender with a blend of 0), so equal ones
    are allowed; an inner cone wider than the outer is an error.
    """
    spot = reader.get(entry, "spot", dict, where, {})
    where = f"{where}.spot"
    inner = reader.get(spot, "innerConeAngle", float, where, DEFAULT_INNER_CONE)
    outer = reader.get(spot, "outerConeAngle", float, where, DEFAULT_OUTER_CONE)
    if not 0.0 <= inner <= outer <= MAX_OUTER_CONE:
        raise reader.fail(
            where,
            f"needs 0 <= innerConeAngle <= outerConeAngle <= pi/2, got innerConeAngle {inner!r:.20}, "
            f"outerConeAngle {outer!r:.20}",
        )
    return inner, outer
