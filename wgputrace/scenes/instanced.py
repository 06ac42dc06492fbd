"""Instances in the Cornell box: one smooth sphere mesh and one box mesh, each stored once and placed
several times, turned, stretched and moved (`Scene.add_instance`), under the box's lamp.

What it checks: the two-level traversal (rays into each instance's object space, t kept), normals
taken back to the world by the inverse transpose (the stretched spheres' smooth shading), and
overlapping instances (two boxes interpenetrate: the nearer surface must win). `scene.flattened()`
is the same picture with every instance's triangles stored apart, which the tests and the Mitsuba
reference render.
"""

from __future__ import annotations

import numpy as np

from ..scene import Diffuse, Glossy, Scene, cornell_box, make_box, make_icosphere, model_matrix

# (position, Euler angles, scale) of each sphere and box instance; scales differ per axis so the
# normals' inverse transpose is not the transform itself
SPHERES = (
    ((-0.28, 0.02, -0.05), (0.3, 0.2, 0.1), (0.12, 0.12, 0.12)),
    ((0.0, 0.0, 0.15), (0.0, 0.7, 0.0), (0.16, 0.1, 0.16)),
    ((0.27, 0.05, -0.12), (0.5, 0.0, 0.9), (0.08, 0.15, 0.1)),
    ((-0.1, 0.55, 0.2), (0.1, 0.1, 0.1), (0.1, 0.1, 0.1)),
)
BOXES = (
    ((0.25, 0.1, 0.25), (0.0, 0.5, 0.0), (0.2, 0.4, 0.2)),
    ((0.32, 0.05, 0.15), (0.2, -0.3, 0.1), (0.18, 0.3, 0.18)),  # interpenetrates the first
)
ORANGE = (0.8, 0.35, 0.1)
SPHERE_ITERATIONS = 2


def instanced_cornell() -> Scene:
    """The walls and lamp of the Cornell box with the instances."""
    scene = cornell_box()
    scene.shapes = [shape for shape in scene.shapes if shape.name.startswith("wall") or shape.name == "lamp"]
    ball = make_icosphere((0, 0, 0), (0, 0, 0), 1.0, SPHERE_ITERATIONS, Diffuse("orange", ORANGE), "ball", smooth=True)
    crate = make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), Glossy("crate", (0.9, 0.9, 0.9), roughness=0.2), "crate")
    for mesh, placements in ((ball, SPHERES), (crate, BOXES)):
        for index, (position, orientation, scale) in enumerate(placements):
            scene.add_instance(mesh, model_matrix(position, orientation, np.array(scale)), f"{mesh.name}{index}")
    return scene
