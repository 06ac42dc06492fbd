"""The ray and lane counters (`count_rays`, `count_lanes`): exact counts where every path's rays
are known in advance, and a counted render that equals the uncounted one bit for bit, so counts
belong to timed paths."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgputrace import Camera, Diffuse, Emitter, Renderer, Scene, default_scene, make_box, make_plane
from wgputrace.kernels.compile import tracing_kernel
from wgputrace.render.ray_count import count_lanes, count_rays

pytestmark = pytest.mark.gpu

SIZE = 16
SPP = 3
SEED = 5
PIXELS = SIZE * SIZE


def closed_box() -> Scene:
    box = make_box((0, 0, 0), (0, 0, 0), (2, 2, 2), Diffuse("white", color=(0.5, 0.5, 0.5)))
    return Scene([box], Camera.looking_at((0, 0, -0.5), (0, 0, 1), vfov_degrees=60))


def test_a_closed_box_without_lights_traces_max_depth_rays_per_path(gpu_context):
    # Inside a closed diffuse box every ray hits a wall and every diffuse sample continues, so each
    # path traces exactly max_depth nearest-hit rays (Russian roulette starts only at depth 3, after
    # the last bounce of a depth-3 path) and, with no light to sample, no shadow ray.
    max_depth = 3
    renderer = Renderer(closed_box(), SIZE, SIZE, seed=SEED, max_depth=max_depth)
    counts = count_rays(renderer, SPP)
    assert (counts.closest_hit, counts.shadow) == (max_depth * PIXELS * SPP, 0)
    assert counts.extension == (max_depth - 1) * PIXELS * SPP


def test_a_lit_floor_traces_one_shadow_ray_per_path(gpu_context):
    # Every pixel sees the floor (camera straight down, narrow view); the lamp above the camera,
    # facing the floor, is out of view. At max depth 2 each path is: camera ray to the floor, one
    # light sample (a shadow ray: the lamp always faces the point), one BSDF-sampled ray upwards.
    floor = make_plane((0, 0, 0), (0, 0, 0), (4, 4), Diffuse("floor"), "floor")
    lamp = make_plane((0, 2, 0), (np.pi, 0, 0), (0.5, 0.5), Emitter("lamp", emittance=5), "lamp")
    scene = Scene([floor, lamp], Camera.looking_at((0, 1, 0), (0, 0, 0.001), vfov_degrees=30))
    renderer = Renderer(scene, SIZE, SIZE, seed=SEED, max_depth=2)
    counts = count_rays(renderer, SPP)
    assert (counts.camera, counts.extension, counts.shadow) == (PIXELS * SPP, PIXELS * SPP, PIXELS * SPP)


def test_the_counted_render_is_the_uncounted_render_bit_for_bit(gpu_context):
    renderer = Renderer(default_scene(), SIZE, SIZE, seed=SEED)
    renderer.render(SPP)
    uncounted = renderer.image()
    renderer.restart()
    counts = count_rays(renderer, SPP)
    np.testing.assert_array_equal(renderer.image(), uncounted)
    # the Cornell box is closed on five sides and lit: paths bounce and sample the lamp
    assert counts.extension > 0 and counts.shadow > 0
    assert renderer.samples_per_pixel == SPP


def test_the_timed_pipeline_has_no_counter(gpu_context):
    renderer = Renderer(default_scene(), SIZE, SIZE, seed=SEED)
    assert "ray_counts" not in renderer.kernel.source.text
    assert "ray_counts" in tracing_kernel(gpu_context, replace(renderer.variant, count_rays=True)).source.text


def lanes_or_skip(renderer: Renderer, spp: int):
    if not renderer.context.has_subgroups:
        pytest.skip("lanes are counted with subgroup operations, which this adapter lacks")
    return count_lanes(renderer, spp)


@pytest.mark.parametrize("samples_per_dispatch", [1, 2])
def test_paths_of_one_length_keep_every_lane_busy(gpu_context, samples_per_dispatch):
    # every path of the closed box has max_depth vertices (above): the lanes of a subgroup start and
    # end their paths together, one pass of the path loop per vertex
    max_depth = 3
    renderer = Renderer(
        closed_box(), SIZE, SIZE, seed=SEED, max_depth=max_depth, samples_per_dispatch=samples_per_dispatch
    )
    lanes = lanes_or_skip(renderer, SPP)
    assert lanes.utilisation("path") == 1.0 and lanes.passes_per_sample("path") == max_depth
    assert 0.0 < lanes.utilisation("traversal") <= 1.0


def test_regeneration_keeps_more_lanes_busy_and_the_counted_render_is_the_render(gpu_context):
    spp = 8
    one = Renderer(default_scene(), SIZE, SIZE, seed=SEED, samples_per_dispatch=1)
    several = Renderer(default_scene(), SIZE, SIZE, seed=SEED, samples_per_dispatch=spp)
    lanes_one, lanes_several = lanes_or_skip(one, spp), count_lanes(several, spp)
    counted = several.image()
    np.testing.assert_array_equal(counted, one.image())
    several.restart()
    several.render(spp)
    np.testing.assert_array_equal(several.image(), counted)
    # roulette ends paths at different lengths: alone a lane waits for its subgroup's longest path
    assert lanes_one.utilisation("path") < lanes_several.utilisation("path")
    assert lanes_several.passes_per_sample("path") < lanes_one.passes_per_sample("path")
