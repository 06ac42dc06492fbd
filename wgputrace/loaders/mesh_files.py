"""PLY and STL through trimesh: one shape of triangles per file, with a grey Diffuse material.

Neither format carries materials we could map (PLY colours are ignored), nor a camera. Vertices are
taken as written (trimesh's `process=False`: no merging, no reordering), faces with more than
three corners are triangulated by trimesh, and closed meshes are wound outwards (`wind_outwards`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..scene import Diffuse, SceneError, Shape
from .errors import SceneLoadError
from .orientation import wind_outwards

DEFAULT_DIFFUSE = 0.8


def read_mesh_file(path: Path) -> list[Shape]:
    import trimesh

    try:
        mesh = trimesh.load_mesh(path, file_type=path.suffix.lower().lstrip("."), process=False)
        vertices = np.asarray(mesh.vertices, dtype=np.float64)
        faces = np.asarray(mesh.faces, dtype=np.int64)
    # trimesh raises whatever its parsers hit on a broken file (struct, index, value, key errors
    # and more); each becomes our one documented error, with trimesh's words in it.
    except Exception as error:  # noqa: BLE001
        raise SceneLoadError(path, f"trimesh cannot read it: {type(error).__name__}: {error}") from None
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise SceneLoadError(path, f"holds no triangles ({len(vertices)} vertices, faces of shape {faces.shape})")
    if faces.min() < 0 or faces.max() >= len(vertices):
        bad = int(np.flatnonzero((faces < 0).any(axis=1) | (faces >= len(vertices)).any(axis=1))[0])
        raise SceneLoadError(path, f"face {bad} {faces[bad].tolist()} refers beyond the {len(vertices)} vertices")
    with np.errstate(over="ignore"):
        triangles = vertices[faces].astype(np.float32)
    wind_outwards(triangles, path, "the mesh", stacklevel=3)
    try:
        return [Shape(path.stem, triangles, Diffuse("default", color=(DEFAULT_DIFFUSE,) * 3))]
    except SceneError as error:
        raise SceneLoadError(path, str(error)) from None
