"""The restir integrator where resampling is known to break: candidates that add nothing (lights
behind the surface, a wall that faces away from every light), one light a million times brighter
than the others, 100,000 lights, and a light switched off between renders. Each picture is
compared with mis's, which the reference tests pin (both unbiased: Welch's test per block of
independent batches), with its own reservoirs and with reservoirs shared between neighbours; none
may hold a non-finite or dropped sample. The references (tests/render/test_references.py) hold it
to Mitsuba on every light kind, and the furnace (test_furnace.py) to its weights against BSDF
sampling summing to one."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Renderer, Scene, Shape, make_box, make_plane
from wgputrace.testing.image_statistics import Estimate, compare_blocks
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SIZE = 32
BLOCK = 8
BATCHES = 8
SPP = 16
SEED = 27
# restir with its own reservoirs (as shipped) and with reservoirs shared between neighbours
SHARING = {"own": {}, "shared": {"RESERVOIR_NEIGHBOURS": 3}}
SCENES = ("lights_behind", "one_bright_light", "hundred_thousand_lights")
FAMILY_SIGNIFICANCE = 1e-3
# every block and channel of every scene, for each kind of reservoir
LEVEL = sidak(FAMILY_SIGNIFICANCE, len(SCENES) * len(SHARING) * 3 * (SIZE // BLOCK) ** 2)
CAMERA = Camera.looking_at((0.0, 2.0, -2.5), (0.0, 0.0, 0.3), vfov_degrees=60.0)


def lamp_grid(count: int, side: float, height: float, size: float, facing_down: bool = True) -> np.ndarray:
    """`count` (a square) small triangles on a grid `side` wide at `height`, facing down or up."""
    per_row = int(round(np.sqrt(count)))
    centres = (np.arange(per_row) + 0.5) / per_row * side - side / 2
    x, z = (grid.ravel() for grid in np.meshgrid(centres, centres))
    triangles = np.zeros((len(x), 3, 3))
    triangles[:, :, 1] = height
    for corner, (dx, dz) in enumerate(((0.0, 0.0), (size, 0.0), (0.0, size))):
        triangles[:, corner, 0] = x + dx
        triangles[:, corner, 2] = z + dz
    normal = np.cross(triangles[0, 1] - triangles[0, 0], triangles[0, 2] - triangles[0, 0])
    if (normal[1] < 0) != facing_down:
        triangles = triangles[:, [0, 2, 1]]
    return triangles


def lights_behind() -> Scene:
    """A floor lit by one lamp above, with 64 lamps under it facing up at its underside and a
    wall that faces away from the lamp: most candidates add nothing, some pixels none at all."""
    floor = make_plane((0, 0, 0), (0, 0, 0), (4.0, 4.0), Diffuse("floor", color=(0.6, 0.6, 0.6)), "floor")
    wall = make_box((0.8, 0.5, 0.8), (0, 0, 0), (0.8, 1.0, 0.05), Diffuse("wall", color=(0.7, 0.5, 0.4)), "wall")
    lamp = make_plane((0.0, 2.0, -0.5), (np.pi, 0, 0), (0.5, 0.5), Emitter("lamp", emittance=10.0), "lamp")
    below = Shape("below", lamp_grid(64, 3.0, -0.5, 0.05, facing_down=False), Emitter("below", emittance=50.0))
    return Scene([floor, wall, lamp, below], CAMERA)


def one_bright_light() -> Scene:
    """400 dim lamps and one of 10^6 times their radiance, the same size: the table draws the
    bright one nearly always, and the dim ones still light the floor far from it."""
    floor = make_plane((0, 0, 0), (0, 0, 0), (4.0, 4.0), Diffuse("floor", color=(0.6, 0.6, 0.6)), "floor")
    dim = Shape("dim", lamp_grid(400, 3.5, 1.2, 0.04), Emitter("dim", emittance=1.0))
    bright = make_plane((1.5, 1.2, 1.5), (np.pi, 0, 0), (0.03, 0.03), Emitter("bright", emittance=1e6), "bright")
    return Scene([floor, dim, bright], CAMERA)


def hundred_thousand_lights() -> Scene:
    """A floor under 100,000 emitting triangles of equal power, and a box between them and part of it."""
    floor = make_plane((0, 0, 0), (0, 0, 0), (4.0, 4.0), Diffuse("floor", color=(0.6, 0.6, 0.6)), "floor")
    box = make_box((0.3, 0.4, 0.4), (0, 0.5, 0), (0.6, 0.8, 0.6), Diffuse("box", color=(0.5, 0.5, 0.6)), "box")
    lights = Shape("lights", lamp_grid(100_000, 4.0, 1.5, 0.004), Emitter("lights", emittance=40.0))
    return Scene([floor, box, lights], CAMERA)


BUILDERS = {"lights_behind": lights_behind, "one_bright_light": one_bright_light}
BUILDERS["hundred_thousand_lights"] = hundred_thousand_lights


def batches(scene: Scene, integrator: str, overrides: dict, seed: int) -> np.ndarray:
    """(BATCHES, SIZE, SIZE, 3) independent images of direct light, none with a non-finite or dropped sample."""
    renderer = Renderer(scene, SIZE, SIZE, seed=seed, max_depth=2, integrator=integrator, shader_overrides=overrides)
    images = []
    for _ in range(BATCHES):
        renderer.render(SPP)
        images.append(renderer.image())
        assert renderer.nonfinite_samples == 0 and renderer.dropped_samples == 0
        renderer.reset()
    return np.stack(images)


def assert_matches_mis(restir: Estimate, mis: Estimate, level: float, what: str) -> None:
    """Every block's mean within Welch's test of mis's at significance `level`."""
    comparison = compare_blocks(restir, mis, BLOCK)
    worst = np.unravel_index(np.argmin(comparison.p_value), comparison.p_value.shape)
    assert comparison.p_value.min() >= level, (
        f"{what}: block {tuple(int(i) for i in worst[:2])} channel {'rgb'[worst[2]]} differs from mis by "
        f"{comparison.difference[worst]:.4g} (z {comparison.z[worst]:.2f}, p {comparison.p_value[worst]:.2g})"
    )


@pytest.mark.parametrize("sharing", SHARING)
@pytest.mark.parametrize("name", SCENES)
def test_restir_converges_to_mis_where_resampling_breaks(gpu_context, name, sharing):
    scene = BUILDERS[name]()
    mis = Estimate.from_batches(batches(scene, "mis", {}, SEED))
    restir = Estimate.from_batches(batches(scene, "restir", SHARING[sharing], SEED + 1))
    assert np.isfinite(restir.mean).all() and restir.mean.max() > 0
    assert_matches_mis(restir, mis, LEVEL, f"{name}, {sharing} reservoirs")


def test_where_no_candidate_adds_light_the_picture_is_black(gpu_context):
    """The wall's side facing away from the lamp, seen by no light but those under the floor,
    which face away from it too: every candidate's target is 0, and the pixels stay 0, not NaN."""
    scene = lights_behind()
    scene.camera = Camera.looking_at((1.2, 0.5, 2.5), (0.8, 0.5, 0.8), vfov_degrees=10.0)
    for overrides in SHARING.values():
        renderer = Renderer(scene, 8, 8, seed=SEED, max_depth=2, integrator="restir", shader_overrides=overrides)
        renderer.render(SPP)
        assert np.all(renderer.image() == 0.0) and renderer.nonfinite_samples == 0


@pytest.mark.parametrize("sharing", SHARING)
def test_a_light_switched_off_leaves_no_light_behind(gpu_context, sharing):
    """After an edit the renderer gives, sample for sample, what a new renderer of the edited
    scene gives: nothing of the reservoirs made under the old light is left."""
    scene = one_bright_light()
    renderer = Renderer(
        scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=SHARING[sharing]
    )
    renderer.render(SPP)
    lit = renderer.image().copy()
    scene.shape("bright").material = Emitter("bright", emittance=0.0)
    renderer.update()
    renderer.render(SPP)
    fresh = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2, integrator="restir", shader_overrides=SHARING[sharing])
    fresh.render(SPP)
    np.testing.assert_array_equal(renderer.image(), fresh.image())
    assert renderer.image().mean() < 0.5 * lit.mean()
