"""Writing small glTF/GLB files for the loader tests: JSON and binary built from numpy arrays, so
every material, node, camera and light field is under the test's control; a box, one material of
each kind the loader maps and one KHR_lights_punctual light of each type to build them from."""

from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

import numpy as np

from wgputrace import Diffuse, make_box

FLOAT, UNSIGNED_INT = 5126, 5125

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
    first = len(document["nodes"])
    document["nodes"] += nodes
    document["scenes"][document.get("scene", 0)]["nodes"] += list(range(first, first + len(nodes)))
    return document


def gltf_document(meshes: list[tuple[np.ndarray, np.ndarray, int | None]], **extra) -> tuple[dict, bytes]:
    """A glTF document with one mesh (one primitive) per (positions (n, 3), indices (m, 3), material
    index) and one root node per mesh, its buffer as bytes; `extra` adds or replaces top-level keys."""
    blob = b""
    accessors, views, gltf_meshes = [], [], []
    for positions, indices, material in meshes:
        for array, kind, component in ((positions, "VEC3", FLOAT), (indices, "SCALAR", UNSIGNED_INT)):
            data = np.ascontiguousarray(array, dtype="<f4" if component == FLOAT else "<u4").tobytes()
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
            accessors.append(
                {
                    "bufferView": len(views) - 1,
                    "componentType": component,
                    "count": array.size // (3 if kind == "VEC3" else 1),
                    "type": kind,
                }
            )
            blob += data
        primitive = {"attributes": {"POSITION": len(accessors) - 2}, "indices": len(accessors) - 1}
        if material is not None:
            primitive["material"] = material
        gltf_meshes.append({"name": f"mesh{len(gltf_meshes)}", "primitives": [primitive]})
    document = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(meshes)))}],
        "nodes": [{"mesh": i} for i in range(len(meshes))],
        "meshes": gltf_meshes,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    document.update(extra)
    return document, blob


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
