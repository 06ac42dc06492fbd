"""Bidirectional path tracing against the path tracer and against itself.

pbrt's debugging method: each strategy (s, t) alone, unweighted (the BDPT_ONLY_S/T overrides),
estimates the paths of s + t - 1 edges that it can sample; on a box of diffuse surfaces every
strategy can sample every path, so each must converge to the path tracer's paths of exactly that
many edges (its image at max_depth k minus its image at k - 1), by Welch's t-test per block and
channel. Then: splat sums alike whatever the order and progressively, max_depth beyond what the
kernel keeps refused, the splat buffer counted before allocating, and no non-finite sample."""

from __future__ import annotations

import warnings
from functools import cache

import numpy as np
import pytest

from wgputrace import Diffuse, Emitter, Renderer, Scene
from wgputrace.gpu.device import DeviceLimitError
from wgputrace.integrators import integrator
from wgputrace.integrators.bdpt import BDPT_MAX_DEPTH
from wgputrace.integrators.splats import SPLATS
from wgputrace.kernels.variant import KernelVariant
from wgputrace.render import limits
from wgputrace.render.limits import check_image_size, host_bytes
from wgputrace.render.renderer import UNLIMITED_DEPTH
from wgputrace.scene import DegenerateTrianglesWarning, cornell_box
from wgputrace.scenes import scene_by_name
from wgputrace.testing.image_statistics import Estimate
from wgputrace.testing.references import assert_same_expectation
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SIZE = 16
BLOCKS = (4, SIZE)
SEED = 18
BATCHES = 8
SPP = 8
FAMILY_SIGNIFICANCE = 1e-3
# (s, t) of every strategy for paths of 3 edges, each kind once: emission found (s = 0), next-event
# estimation (s = 1), a connection between stored vertices (2, 2) and light tracing, whose splats
# reach image() and go with reset() (3, 1). Those of 2 edges, the same code at one vertex less, are
# left out: each strategy costs a kernel compile in CI.
STRATEGIES = ((0, 4), (1, 3), (2, 2), (3, 1))
# Built-in scenes that no other bdpt test renders to radiance (the bdpt reference cases assert no
# non-finite sample on their own): the tiny lamp, the
# box 1e4 times its size, zero-area triangles, an environment black but for one texel (densities
# that round to 0), and glass at grazing angles (total internal reflection on light paths).
NAN_SCENES = ("tiny_light", "cornell_1e4", "slivers", "env_one_texel", "glass_grazing")
BLOCK_TESTS = sum((SIZE // block) ** 2 for block in BLOCKS) * 3
PER_TEST_SIGNIFICANCE = sidak(FAMILY_SIGNIFICANCE, BLOCK_TESTS * len(STRATEGIES))


def diffuse_box() -> Scene:
    """The Cornell box with its glass and glossy surfaces made white diffuse: every vertex connects."""
    box = cornell_box()
    white = Diffuse("white", color=(0.74, 0.74, 0.73))
    for shape in box.shapes:
        if not isinstance(shape.material, (Diffuse, Emitter)):
            shape.material = white
    return box


def batches(max_depth: int, integrator: str, overrides: dict | None = None, spp: int = SPP) -> np.ndarray:
    renderer = Renderer(
        diffuse_box(), SIZE, SIZE, seed=SEED, max_depth=max_depth, integrator=integrator, shader_overrides=overrides
    )
    images = []
    for _ in range(BATCHES):
        renderer.render(spp)
        images.append(renderer.image())
        renderer.reset()
    assert renderer.nonfinite_samples == 0
    return np.stack(images)


@cache
def paths_of_exactly(edges: int) -> Estimate:
    """The path tracer's estimate of the paths of exactly `edges` edges."""
    longer, shorter = Estimate.from_batches(batches(edges, "mis")), Estimate.from_batches(batches(edges - 1, "mis"))
    return Estimate(longer.mean - shorter.mean, longer.variance + shorter.variance, float(BATCHES - 1))


@pytest.mark.slow
@pytest.mark.parametrize("strategy", STRATEGIES, ids=[f"s{s}_t{t}" for s, t in STRATEGIES])
def test_each_strategy_alone_converges_to_the_paths_it_samples(gpu_context, failure_dir, strategy):
    s, t = strategy
    edges = s + t - 1
    alone = Estimate.from_batches(batches(edges, "bdpt", {"BDPT_ONLY_S": s, "BDPT_ONLY_T": t}))
    expected = paths_of_exactly(edges)
    assert alone.mean.mean() > 0.01, f"strategy {strategy} found no light"
    assert_same_expectation(
        f"bdpt_s{s}_t{t}",
        alone,
        expected,
        expected.mean,
        0.0,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=PER_TEST_SIGNIFICANCE,
    )


def test_same_seed_same_image_and_progressive(gpu_context):
    def rendered(*counts: int) -> np.ndarray:
        renderer = Renderer(diffuse_box(), SIZE, SIZE, seed=SEED, max_depth=4, integrator="bdpt")
        for count in counts:
            renderer.render(count)
        return renderer.image()

    once = rendered(4)
    assert np.array_equal(once, rendered(4))
    assert np.array_equal(rendered(2, 2), once)


@pytest.mark.parametrize("max_depth", [UNLIMITED_DEPTH, BDPT_MAX_DEPTH + 1])
def test_depth_beyond_the_kept_light_vertices_is_refused(gpu_context, max_depth):
    with pytest.raises(ValueError, match=f"integrator 'bdpt' takes max_depth from 1 to {BDPT_MAX_DEPTH}"):
        Renderer(diffuse_box(), SIZE, SIZE, max_depth=max_depth, integrator="bdpt")


def test_no_band_of_rows_kernel(gpu_context):
    """The viewer renders bands of rows; light tracing splats anywhere in the image, so bdpt has no
    such kernel and its variant says so in one line (`wgputrace view` offers no --integrator)."""
    with pytest.raises(ValueError, match="bdpt integrator renders whole images only: it has no band-of-rows"):
        KernelVariant(integrator=integrator("bdpt"), rows=True)


@pytest.mark.slow
@pytest.mark.parametrize("scene", NAN_SCENES)
def test_no_nan_or_infinity(gpu_context, scene):
    """No sample or splat is NaN or infinite, through every strategy."""
    with warnings.catch_warnings():
        # the slivers scene drops its zero-area triangles on purpose
        warnings.simplefilter("ignore", DegenerateTrianglesWarning)
        renderer = Renderer(scene_by_name(scene), SIZE, SIZE, seed=SEED, integrator="bdpt")
    renderer.render(4)
    assert renderer.nonfinite_samples == 0
    assert np.isfinite(renderer.image()).all()


def test_the_splat_buffer_is_counted_before_allocating(gpu_context, monkeypatch):
    """The limits count the splat sums as the renderer allocates them; a host with just
    enough memory for the path tracer's image refuses the same image under bdpt, in one line."""
    renderer = Renderer(diffuse_box(), SIZE, SIZE, integrator="bdpt")
    assert renderer.gpu_image_bytes["splats"] == SIZE * SIZE * SPLATS.bytes_per_pixel
    side = 1024
    monkeypatch.setattr(limits, "available_host_memory", lambda: host_bytes(gpu_context, side * side))
    check_image_size(gpu_context, side, side)
    with pytest.raises(DeviceLimitError, match=r"available host memory .* under bdpt is \d") as error:
        Renderer(diffuse_box(), side, side, integrator="bdpt")
    assert "\n" not in str(error.value)
