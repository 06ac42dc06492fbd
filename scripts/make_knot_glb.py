"""Write a smooth trefoil-knot tube as an uncompressed .glb (POSITION, NORMAL, indices; a glossy
gold material; a sun from the upper left), the input docs/guide/scene_files.md runs through gltfpack to make its
meshopt-compressed example.

    python scripts/make_knot_glb.py knot.glb
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from wgputrace.testing.gltf_files import (
    MATERIALS,
    gltf_document,
    light_node,
    with_lights,
    with_vertex_attribute,
    write_glb,
)

ALONG, AROUND = 512, 48  # vertices along the knot and around the tube
TUBE_RADIUS = 0.35
SUN = {"type": "directional", "color": [1, 0.95, 0.9], "intensity": 3}
SUN_ROTATION = [-0.33, -0.2, 0.0, 0.92]  # a quaternion turning the sun's -z down and to the right


def knot() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The tube's vertices, unit normals and triangles (a closed grid, wrapping both ways)."""
    t = np.linspace(0, 2 * np.pi, ALONG, endpoint=False)
    centre = np.stack([np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t), -np.sin(3 * t)], axis=1)
    tangent = np.stack([np.cos(t) + 4 * np.cos(2 * t), -np.sin(t) + 4 * np.sin(2 * t), -3 * np.cos(3 * t)], axis=1)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    side = np.cross(tangent, [0.0, 0.0, 1.0])
    side /= np.linalg.norm(side, axis=1, keepdims=True)
    up = np.cross(side, tangent)
    angle = np.linspace(0, 2 * np.pi, AROUND, endpoint=False)
    normals = np.cos(angle)[None, :, None] * side[:, None] + np.sin(angle)[None, :, None] * up[:, None]
    positions = centre[:, None] + TUBE_RADIUS * normals
    i, j = np.meshgrid(np.arange(ALONG), np.arange(AROUND), indexing="ij")
    a, b = i * AROUND + j, (i + 1) % ALONG * AROUND + j
    c, d = (i + 1) % ALONG * AROUND + (j + 1) % AROUND, i * AROUND + (j + 1) % AROUND
    triangles = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return positions.reshape(-1, 3).astype(np.float32), normals.reshape(-1, 3).astype(np.float32), triangles


def main(path: Path) -> None:
    positions, normals, triangles = knot()
    gold = MATERIALS[3]
    document, blob = gltf_document([(positions, triangles, 0)], materials=[gold])
    blob = with_vertex_attribute(document, blob, 0, "NORMAL", normals)
    document = with_lights(document, [SUN], [light_node(0, rotation=SUN_ROTATION)])
    write_glb(path, document, blob)


if __name__ == "__main__":
    main(Path(sys.argv[1]))
