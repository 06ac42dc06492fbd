"""Draco-compressed glTF meshes (KHR_draco_mesh_compression), decoded through DracoPy, the `draco`
extra; imported on first use, so that the glTF loader works without it and says how to get it.

DracoPy is Google's own Draco decoder in a small dependency-free wheel, and it encodes too, so
the tests compress their own meshes. A Draco primitive's extension names one bufferView of
compressed bytes and maps each glTF attribute to a Draco attribute id; the primitive's accessors
keep their count, componentType and type, and the decoded arrays stand in for their data.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

DRACO_EXTENSION = "KHR_draco_mesh_compression"
DRACO_INSTALL_HINT = 'pip install "wgputrace[draco]"'


class DracoMissing(ImportError):
    """DracoPy is not installed: the message says how to install it."""


class DracoDecodeError(ValueError):
    """Bytes that do not decode as a Draco mesh."""


class DracoMesh(NamedTuple):
    """A decoded Draco mesh: triangles as (n, 3) uint32 vertex indices, and each attribute's
    (vertices, components) array by its Draco attribute id."""

    triangles: np.ndarray
    attributes: dict[int, np.ndarray]


def draco_available() -> bool:
    try:
        import DracoPy  # noqa: F401
    except ImportError:
        return False
    return True


def decode_draco(data: bytes) -> DracoMesh:
    try:
        import DracoPy
    except ImportError:
        raise DracoMissing(f"{DRACO_EXTENSION} needs DracoPy: {DRACO_INSTALL_HINT}") from None
    try:
        mesh = DracoPy.decode(bytes(data))
    except Exception as error:  # DracoPy raises bare Exceptions (FileTypeException, decoding errors)
        raise DracoDecodeError(f"the Draco bytes do not decode: {error}") from None
    if not isinstance(mesh, DracoPy.DracoMesh):
        raise DracoDecodeError("the Draco bytes hold a point cloud, not a mesh")
    attributes = {entry["unique_id"]: np.asarray(entry["data"]) for entry in mesh.attributes}
    triangles = np.asarray(mesh.faces, dtype=np.uint32).reshape(-1, 3)
    return DracoMesh(triangles, {key: value.reshape(len(value), -1) for key, value in attributes.items()})
