"""Writing meshopt-compressed GLB files for the loader tests: a glTF document (as
`gltf_files.gltf_document` builds it) with every view an accessor reads compressed through the
`meshopt` package's encoder, the way gltfpack stores it: the compressed bytes in the GLB's buffer 0,
the bufferViews themselves pointing into a fallback buffer 1.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path

import numpy as np

from .gltf_files import write_glb

EXT = "EXT_meshopt_compression"
KHR = "KHR_meshopt_compression"


def meshopt_glb(path: Path, document: dict, blob: bytes, *args, **kwargs) -> Path:
    """`meshopt_compressed(document, blob, ...)` written to `path` as a GLB."""
    return write_glb(path, *meshopt_compressed(document, blob, *args, **kwargs))


def meshopt_compressed(
    document: dict,
    blob: bytes,
    extension: str = EXT,
    filtered: dict[int, tuple[str, np.ndarray]] | None = None,
    index_mode: str = "TRIANGLES",
    fallback_data: bool = False,
) -> tuple[dict, bytes]:
    """`document` (its data in `blob`, buffer 0) with each bufferView an accessor reads compressed by `extension`: a primitive's indices in `index_mode`, the rest as ATTRIBUTES,
    `filtered[view]` = (filter, the filter's encoded rows from meshopt.encode_filter_*) for a view
    whose data is filtered; other views (images) stay uncompressed in buffer 0. The fallback buffer holds the decoded data as a data URI where
    `fallback_data`, else nothing (no uri) and the extension is required. Returns the new document
    and its GLB binary chunk."""
    import meshopt

    document = json.loads(json.dumps(document))
    filtered = filtered or {}
    index_views = {
        document["accessors"][primitive["indices"]]["bufferView"]
        for mesh in document["meshes"]
        for primitive in mesh["primitives"]
        if "indices" in primitive
    }
    strides = {accessor["bufferView"]: element_size(accessor) for accessor in document["accessors"]}
    compressed, fallback = b"", bytearray(blob)
    for number, view in enumerate(document["bufferViews"]):
        if number not in strides:  # an image's bytes: kept uncompressed, moved into the GLB's buffer
            start = view.get("byteOffset", 0)
            view["byteOffset"] = len(compressed)
            compressed += blob[start : start + view["byteLength"]]
            compressed += b"\0" * (-len(compressed) % 4)
            continue
        stride = view.get("byteStride", strides[number])
        data = np.frombuffer(blob, np.uint8, view["byteLength"], view.get("byteOffset", 0)).reshape(-1, stride)
        mode = index_mode if number in index_views else "ATTRIBUTES"
        filter_, rows = filtered.get(number, ("NONE", data))
        if mode != "ATTRIBUTES":
            rows = data.copy().view(np.uint16 if stride == 2 else np.uint32).ravel()
        encoded = meshopt.encode_gltf_buffer(rows, mode, version=1 if extension == KHR else 0)
        decoded = meshopt.decode_gltf_buffer(encoded, len(data), stride, mode, filter_)
        start = view.get("byteOffset", 0)
        fallback[start : start + view["byteLength"]] = decoded.tobytes()
        block = {"buffer": 0, "byteOffset": len(compressed), "byteLength": len(encoded), "byteStride": stride}
        block |= {"count": len(data), "mode": mode} | ({"filter": filter_} if filter_ != "NONE" else {})
        view.update(buffer=1, extensions={extension: block})
        compressed += encoded + b"\0" * (-len(encoded) % 4)
    extra = {"uri": "data:application/octet-stream;base64," + base64.b64encode(fallback).decode()}
    document["buffers"] = [
        {"byteLength": len(compressed)},
        {
            "byteLength": len(fallback),
            **(extra if fallback_data else {}),
            "extensions": {extension: {"fallback": True}},
        },
    ]
    document["extensionsUsed"] = [*document.get("extensionsUsed", []), extension]
    if not fallback_data:
        document["extensionsRequired"] = [*document.get("extensionsRequired", []), extension]
    return document, compressed


COMPONENT_SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def element_size(accessor: dict) -> int:
    return COMPONENT_SIZES[accessor["componentType"]] * COMPONENTS[accessor["type"]]
