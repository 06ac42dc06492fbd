"""A ceiling lit by the top of a lamp hanging just below it (the Cornell box's lamp, 0.05 under
the ceiling): the ceiling sees the lamp at grazing angles, in closed form.

The Mitsuba comparison found this: next-event estimation's shadow ray started at the origin moved
off the ceiling (towards the lamp's plane) but kept the length measured from the unmoved point, so
at grazing angles it reached the lamp and counted it as its own occluder; the ceiling lost most of
its direct light and the whole box darkened by about 5%. Every integrator must give the closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from wgputrace import Camera, Renderer, Scene
from wgputrace.integrators import integrator_names
from wgputrace.scene import cornell_box
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.slow

SIZE = 4
# A pinhole this narrow sees one point of the ceiling (the radiance changes by ~1e-3 across it).
VFOV_DEGREES = 0.01
SEED = 5
BATCHES = 8
SPP = 256
# Ceiling points behind the lamp (its far edge is at z = 0.1), where it is seen at 45 and 10 degrees.
CEILING_Z = (0.15, 0.3)
SIGNIFICANCE = 1e-3
TESTS = len(integrator_names()) * len(CEILING_Z) * 3


def corner_factor(a: float, b: float) -> float:
    """Configuration factor from a point to a parallel a x b rectangle at distance 1 whose corner
    lies on the point's normal (Howell's catalogue of configuration factors)."""
    ra, rb = math.hypot(1.0, a), math.hypot(1.0, b)
    return (a / ra * math.atan(b / ra) + b / rb * math.atan(a / rb)) / (2.0 * math.pi)


def rectangle_factor(x: tuple[float, float], z: tuple[float, float], distance: float) -> float:
    """Factor to the rectangle x[0]..x[1] by z[0]..z[1] (relative to the point's foot), by signed corners."""

    def signed(u: float, v: float) -> float:
        return math.copysign(1.0, u) * math.copysign(1.0, v) * corner_factor(abs(u) / distance, abs(v) / distance)

    return signed(x[1], z[1]) - signed(x[0], z[1]) - signed(x[1], z[0]) + signed(x[0], z[0])


def lamp_and_ceiling(ceiling_z: float) -> tuple[Scene, np.ndarray]:
    """The lamp and the ceiling of the Cornell box, a camera looking straight up at the ceiling
    point (0, y, ceiling_z), and that point's exact radiance (direct light only)."""
    shapes = {shape.name: shape for shape in cornell_box().shapes}
    lamp, ceiling = shapes["lamp"], shapes["wall_top"]
    lamp_corners, ceiling_y = lamp.vertices.reshape(-1, 3).astype(np.float64), float(ceiling.vertices[0, 0, 1])
    low, high = lamp_corners.min(axis=0), lamp_corners.max(axis=0)
    factor = rectangle_factor((low[0], high[0]), (low[2] - ceiling_z, high[2] - ceiling_z), ceiling_y - low[1])
    radiance = np.asarray(ceiling.material.color) * np.asarray(lamp.material.radiance) * factor
    camera = Camera((0.0, 0.5, ceiling_z), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), VFOV_DEGREES)
    return Scene([lamp, ceiling], camera), radiance


@pytest.mark.parametrize("ceiling_z", CEILING_Z)
@pytest.mark.parametrize("integrator", integrator_names())
def test_ceiling_above_a_lamp_gets_the_closed_form_light(gpu_context, integrator, ceiling_z):
    scene, expected = lamp_and_ceiling(ceiling_z)
    # max depth 2: the ceiling's direct light, nothing else
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator=integrator)
    means = []
    for _ in range(BATCHES):
        renderer.render(SPP)
        means.append(renderer.image().reshape(-1, 3).mean(axis=0, dtype=np.float64))
        renderer.reset()
    means = np.array(means)
    mean, standard_error = means.mean(axis=0), means.std(axis=0, ddof=1) / math.sqrt(BATCHES)
    assert np.all(standard_error > 0)
    p = 2.0 * stats.t.sf(np.abs(mean - expected) / standard_error, BATCHES - 1)
    assert p.min() >= sidak(SIGNIFICANCE, TESTS), (
        f"{integrator}: {mean} +- {standard_error}, closed form {expected}, p {p}"
    )
