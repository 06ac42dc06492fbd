"""Writing small glTF/GLB files for the loader tests: JSON and binary built from numpy arrays, so
every material, node, camera and light field is under the test's control; a box, one material of
each kind the loader maps and one KHR_lights_punctual light of each type to build them from; and
textures: PNG images generated here, embedded in the binary buffer, as data URIs or as files."""

from __future__ import annotations

import base64
import io
import json
import struct
import zlib
from pathlib import Path

import numpy as np
from PIL import Image

from wgputrace import Diffuse, make_box
from wgputrace.scenes.textured_asset import floor as asset_floor
from wgputrace.scenes.textured_asset import panel as asset_panel

FLOAT, UNSIGNED_INT = 5126, 5125
ACCESSOR_TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}

BOX = make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Diffuse("unused")).vertices.reshape(-1, 3)
BOX_INDICES = np.arange(len(BOX)).reshape(-1, 3)
# One glTF material per kind the loader maps: diffuse, glass, emitter, glossy.
MATERIALS = [
    {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0.0}},
    {
        "name": "glass",
        "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 1, 1], "metallicFactor": 0.0},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.33}},
    },
    {
        "name": "lamp",
        "emissiveFactor": [1, 0.5, 0.25],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8}},
    },
    {"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1, 0.8, 0.3, 1], "roughnessFactor": 0.5}},
]


# One KHR_lights_punctual light of each type, every field set (range, which the loader ignores, too).
LIGHTS = [
    {"name": "bulb", "type": "point", "color": [1, 0.9, 0.8], "intensity": 40, "range": 10},
    {"type": "spot", "color": [1, 1, 1], "intensity": 200, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}},
    {"type": "directional", "color": [1, 1, 0.9], "intensity": 3},
]


def light_node(light: int, **transform) -> dict:
    """A node placing light number `light` of the extension; `transform`: the node's translation,
    rotation, scale or matrix, as glTF writes them."""
    return {"extensions": {"KHR_lights_punctual": {"light": light}}, **transform}


def with_lights(document: dict, lights: list[dict], nodes: list[dict]) -> dict:
    """`document` declaring KHR_lights_punctual's `lights`, with `nodes` added as roots of its scene."""
    document.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
    document.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": lights}
    return with_roots(document, nodes)


# A perspective camera in front of the origin and an orthographic one above it looking down, every
# field glTF defines set, and the nodes placing them.
CAMERAS = [
    {
        "name": "front",
        "type": "perspective",
        "perspective": {"yfov": 0.7, "aspectRatio": 1.5, "znear": 0.1, "zfar": 99},
    },
    {"name": "top", "type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.5, "znear": 0.0, "zfar": 50}},
]
CAMERA_NODES = [
    {"camera": 0, "translation": [0, 0.5, 6]},
    {"camera": 1, "translation": [0, 5, 0], "rotation": [-(0.5**0.5), 0, 0, 0.5**0.5]},
]


def with_cameras(document: dict, cameras: list[dict], nodes: list[dict]) -> dict:
    """`document` with `cameras`, and `nodes` (placing them) added as roots of its scene."""
    document["cameras"] = cameras
    return with_roots(document, nodes)


def box_with_cameras(path: Path) -> Path:
    """A GLB of a red box seen by CAMERAS (placed by CAMERA_NODES), written at `path`."""
    document, blob = gltf_document([(BOX, BOX_INDICES, 0)], materials=json.loads(json.dumps(MATERIALS[:1])))
    return write_glb(path, with_cameras(document, *json.loads(json.dumps([CAMERAS, CAMERA_NODES]))), blob)


def with_roots(document: dict, nodes: list[dict]) -> dict:
    """`document` with `nodes` added as roots of its scene."""
    first = len(document["nodes"])
    document["nodes"] += nodes
    document["scenes"][document.get("scene", 0)]["nodes"] += list(range(first, first + len(nodes)))
    return document


def gltf_document(meshes: list[tuple[np.ndarray, np.ndarray, int | None]], **extra) -> tuple[dict, bytes]:
    """A glTF document with one mesh (one primitive) per (positions (n, 3), indices (m, 3), material
    index) and one root node per mesh, its buffer as bytes; `extra` adds or replaces top-level keys."""
    document = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(meshes)))}],
        "nodes": [{"mesh": i} for i in range(len(meshes))],
        "meshes": [],
        "accessors": [],
        "bufferViews": [],
        "buffers": [{"byteLength": 0}],
    }
    blob = b""
    for positions, indices, material in meshes:
        position, blob = add_accessor(document, blob, np.asarray(positions).reshape(-1, 3), FLOAT)
        index, blob = add_accessor(document, blob, np.asarray(indices).reshape(-1, 1), UNSIGNED_INT)
        primitive = {"attributes": {"POSITION": position}, "indices": index}
        if material is not None:
            primitive["material"] = material
        document["meshes"].append({"name": f"mesh{len(document['meshes'])}", "primitives": [primitive]})
    document.update(extra)
    return document, blob


def add_view(document: dict, blob: bytes, data: bytes) -> tuple[int, bytes]:
    """`data` appended to the buffer (4-byte aligned) as a new bufferView: its index, the new buffer."""
    blob += b"\0" * (-len(blob) % 4)
    document["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
    document["buffers"][0]["byteLength"] = len(blob) + len(data)
    return len(document["bufferViews"]) - 1, blob + data


def add_accessor(document: dict, blob: bytes, rows: np.ndarray, component: int) -> tuple[int, bytes]:
    """(count, k) `rows` as a new accessor of `component` type: its index, the new buffer."""
    view, blob = add_view(document, blob, np.ascontiguousarray(rows, "<f4" if component == FLOAT else "<u4").tobytes())
    accessor = {
        "bufferView": view,
        "componentType": component,
        "count": len(rows),
        "type": ACCESSOR_TYPES[rows.shape[1]],
    }
    document["accessors"].append(accessor)
    return len(document["accessors"]) - 1, blob


def with_vertex_attribute(document: dict, blob: bytes, mesh: int, semantic: str, rows: np.ndarray) -> bytes:
    """Mesh `mesh`'s primitive given per-vertex float `rows` as attribute `semantic`; the new buffer."""
    index, blob = add_accessor(document, blob, np.asarray(rows, np.float32), FLOAT)
    document["meshes"][mesh]["primitives"][0]["attributes"][semantic] = index
    return blob


def png_bytes(pixels: np.ndarray) -> bytes:
    """uint8 (H, W, C) pixels encoded as a PNG file."""
    stream = io.BytesIO()
    Image.fromarray(np.asarray(pixels, np.uint8).squeeze()).save(stream, format="PNG")
    return stream.getvalue()


def marked_pixels(size: int = 4) -> np.ndarray:
    """uint8 (size, size, 4) mid-grey RGBA with a red top-left texel and a transparent bottom-right
    one, so that a flip or a swap of the axes shows."""
    pixels = np.full((size, size, 4), 128, np.uint8)
    pixels[..., 3] = 255
    pixels[0, 0] = (255, 0, 0, 255)
    pixels[-1, -1, 3] = 0
    return pixels


def with_images(document: dict, blob: bytes, images: list[bytes], how: str, directory: Path | None = None) -> bytes:
    """`images` (encoded files) added as glTF images and one texture each (texture i uses image i),
    stored `how`: "bufferView" (in the binary buffer), "data" (base64 data URIs) or "file" (files
    image<i>.png in `directory`, referenced by relative URI); the new buffer."""
    entries = []
    for number, data in enumerate(images):
        if how == "bufferView":
            view, blob = add_view(document, blob, data)
            entries.append({"bufferView": view, "mimeType": "image/png"})
        elif how == "data":
            entries.append({"uri": "data:image/png;base64," + base64.b64encode(data).decode()})
        else:
            (directory / f"image{number}.png").write_bytes(data)
            entries.append({"uri": f"image{number}.png"})
    document["images"] = entries
    document["textures"] = [{"source": number} for number in range(len(images))]
    return blob


def write_glb(path: Path, document: dict, blob: bytes) -> Path:
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)
    return path


def write_gltf(path: Path, document: dict, blob: bytes) -> Path:
    """A .gltf whose buffer is a base64 data URI."""
    document = json.loads(json.dumps(document))
    document["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    path.write_text(json.dumps(document))
    return path


SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
SQUARE_INDICES = np.array([[0, 1, 2], [0, 2, 3]])
# glTF's v runs down the image: the square's (0, 0) corner reads the image's bottom-left
SQUARE_UVS = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
SQUARE_TANGENTS = np.array([[1, 0, 0, 1]] * 4, np.float32)
# A material using every texture slot (all the same image), a sampler, a transform and alpha.
TEXTURED_MATERIAL = {
    "name": "textured",
    "pbrMetallicRoughness": {
        "baseColorFactor": [1, 0.5, 0.5, 0.8],
        "baseColorTexture": {"index": 0},
        "metallicFactor": 0.25,
        "roughnessFactor": 0.75,
        "metallicRoughnessTexture": {
            "index": 0,
            "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.5, "scale": [2, 3]}},
        },
    },
    "normalTexture": {"index": 0, "scale": 0.5},
    "occlusionTexture": {"index": 0},
    "emissiveFactor": [1, 1, 1],
    "emissiveTexture": {"index": 0},
    "alphaMode": "MASK",
    "alphaCutoff": 0.25,
    "doubleSided": True,
    "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}, "KHR_materials_ior": {"ior": 1.4}},
}


def textured_square(how: str = "bufferView", directory: Path | None = None, material: dict | None = None):
    """A unit square with TEXCOORD_0 and TANGENT, TEXTURED_MATERIAL (or `material`) on it, its
    image marked_pixels() stored `how` (see with_images), its texture sampled with clamp on s and
    mirror on t: (document, buffer)."""
    document, blob = gltf_document(
        [(SQUARE, SQUARE_INDICES, 0)],
        materials=[json.loads(json.dumps(material or TEXTURED_MATERIAL))],
        extensionsUsed=["KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_ior"],
    )
    blob = with_vertex_attribute(document, blob, 0, "TEXCOORD_0", SQUARE_UVS)
    blob = with_vertex_attribute(document, blob, 0, "TANGENT", SQUARE_TANGENTS)
    blob = with_images(document, blob, [png_bytes(marked_pixels())], how, directory)
    document["samplers"] = [{"wrapS": 33071, "wrapT": 33648, "magFilter": 9729}]
    document["textures"][0]["sampler"] = 0
    return document, blob


def png_header(width: int, height: int) -> bytes:
    """A PNG claiming `width` x `height` 8-bit RGB pixels whose data stream is empty: what a reader
    sees before it decodes anything."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", b"") + chunk(b"IEND", b"")


def textured_asset_glb(path: Path) -> Path:
    """The panel and floor of the built-in `textured_asset` scene written as a .glb: the panel's
    NORMAL and TEXCOORD_0 per vertex (corners not shared), its four textures as embedded PNGs (their
    8-bit texels), its factors, normal scale and emissive strength; the camera and light are the
    scene's, not the file's. Loading it gives the scene's model.
    """
    shapes = asset_panel(), asset_floor()
    meshes = [
        (shape.vertices.reshape(-1, 3), np.arange(3 * len(shape.vertices)).reshape(-1, 3), i)
        for i, shape in enumerate(shapes)
    ]
    panel, floor = (shape.material for shape in shapes)
    textures = (
        panel.base_color_texture,
        panel.metallic_roughness_texture,
        panel.normal_texture,
        panel.emission_texture,
    )
    materials = [
        {
            "name": panel.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [*panel.base_color, 1.0],
                "baseColorTexture": {"index": 0},
                "metallicFactor": panel.metallic,
                "roughnessFactor": panel.roughness,
                "metallicRoughnessTexture": {"index": 1},
            },
            "normalTexture": {"index": 2, "scale": panel.normal_scale},
            "emissiveFactor": list(panel.emission),
            "emissiveTexture": {"index": 3},
            "doubleSided": True,
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": panel.emission_strength}},
        },
        {
            "name": floor.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [*floor.color, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0,
            },
            "doubleSided": True,
        },
    ]
    document, blob = gltf_document(meshes, materials=materials, extensionsUsed=["KHR_materials_emissive_strength"])
    # the floor has neither: flat and untextured, as glTF reads a primitive without them
    blob = with_vertex_attribute(document, blob, 0, "NORMAL", shapes[0].normals.reshape(-1, 3))
    blob = with_vertex_attribute(document, blob, 0, "TEXCOORD_0", shapes[0].uvs.reshape(-1, 2))
    blob = with_images(document, blob, [png_bytes(texture.encoded_texels) for texture in textures], "bufferView")
    return write_glb(path, document, blob)
