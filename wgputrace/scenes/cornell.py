"""The trac0r Cornell box and variants of it that break path tracers in known ways.

- `tiny_light`: the ceiling lamp shrunk to 1e-4 of its area with its power kept (radiance times
  1e4). The image barely changes; the variance of paths that must find the lamp by chance grows
  about 1e4-fold, and anything that loses precision on small, bright lights shows.
- `scaled_cornell`: the whole box, camera included, scaled by a factor. The image must not change:
  every tolerance that is absolute instead of relative to the scene shows up at 1e-4 or 1e4.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Emitter, Scene, Shape, cornell_box

TINY_LIGHT_AREA_FRACTION = 1e-4
LAMP = "lamp"


def cornell() -> Scene:
    """The trac0r Cornell box (listing 16 of the thesis)."""
    return cornell_box()


def tiny_light() -> Scene:
    """The Cornell box with a lamp of 1e-4 the area and the same emitted power."""
    scene = cornell_box()
    shrink = np.sqrt(TINY_LIGHT_AREA_FRACTION)
    shapes = []
    for shape in scene.shapes:
        if shape.name == LAMP:
            lamp = shape.material
            # the lamp lies in a plane y = const: shrink it in x and z about its centre
            centre = shape.vertices.reshape(-1, 3).astype(np.float64).mean(axis=0)
            matrix = np.eye(4)
            matrix[:3, :3] = np.diag([shrink, 1.0, shrink])
            matrix[:3, 3] = centre - matrix[:3, :3] @ centre
            light = Emitter(lamp.name, color=lamp.color, emittance=lamp.emittance / TINY_LIGHT_AREA_FRACTION)
            shape = Shape(shape.name, shape.transformed(matrix).vertices, light)
        shapes.append(shape)
    return Scene(shapes, scene.camera)


def scaled_cornell(factor: float) -> Scene:
    """The Cornell box with every vertex and the camera position multiplied by `factor`."""
    scene = cornell_box()
    camera = scene.camera
    scaled_camera = Camera(np.multiply(camera.position, factor), camera.forward, camera.up, camera.vfov_degrees)
    return Scene([shape.transformed(np.eye(3) * factor) for shape in scene.shapes], scaled_camera)
