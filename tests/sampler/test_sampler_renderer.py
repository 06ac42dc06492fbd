"""Renderer(sampler=...): the Sobol sampler's samples continue across render calls (16 + 16 == 32,
bit for bit), go back to the seed on restart, start a new scramble on reset, differ with the seed,
and give no non-finite sample where the independent sampler gives none."""

from __future__ import annotations

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.scenes import BUILTIN_SCENES

pytestmark = pytest.mark.gpu

SIZE = 24
SEED = 5


def sobol_renderer(scene: str = "cornell", seed: int = SEED, **options) -> wt.Renderer:
    return wt.Renderer(BUILTIN_SCENES[scene](), SIZE, SIZE, seed=seed, sampler="sobol", **options)


def image_after(renderer: wt.Renderer, *spp: int) -> np.ndarray:
    for count in spp:
        renderer.render(count)
    return renderer.image()


def test_samples_continue_across_render_calls():
    halves = sobol_renderer()
    first_half = image_after(halves, 16)
    assert np.array_equal(first_half, image_after(sobol_renderer(), 16))
    assert np.array_equal(image_after(halves, 16), image_after(sobol_renderer(), 32))


def test_restart_repeats_and_reset_rescrambles():
    """restart goes back to every pixel's first sample; reset starts the next replicate, the same
    sample counts under another scramble (`test_user_seeds_and_replicates_scramble_independently`:
    independent of the first), which the next restart forgets."""
    renderer = sobol_renderer()
    first = image_after(renderer, 8)
    renderer.restart()
    assert np.array_equal(image_after(renderer, 8), first)
    renderer.reset()
    replicate = image_after(renderer, 8)
    assert np.mean(replicate != first) > 0.9
    renderer.restart()
    assert np.array_equal(image_after(renderer, 8), first)


def test_the_seed_decides_the_image():
    first = image_after(sobol_renderer(seed=1), 4)
    assert np.array_equal(image_after(sobol_renderer(seed=1), 4), first)
    assert np.mean(image_after(sobol_renderer(seed=2), 4) != first) > 0.9


@pytest.mark.parametrize("scene", ["tiny_light", "cornell_1e-4", "cornell_1e4", "alpha_cutout"])
def test_no_nonfinite_samples(scene):
    renderer = sobol_renderer(scene)
    image = image_after(renderer, 8)
    assert renderer.nonfinite_samples == 0
    assert np.isfinite(image).all() and image.max() > 0.0


def test_unknown_sampler_is_refused():
    with pytest.raises(ValueError, match="sampler must be one of independent, sobol, got 'halton'"):
        wt.Renderer(BUILTIN_SCENES["cornell"](), SIZE, SIZE, sampler="halton")


@pytest.mark.parametrize("sampler", ["sobol", "independent"])
def test_restart_at_another_seed_is_a_fresh_renderer_of_it(sampler):
    """restart(seed) (a cluster worker's next batch) continues as a Renderer built with that seed,
    and a later restart() goes back to it."""
    renderer = wt.Renderer(BUILTIN_SCENES["cornell"](), SIZE, SIZE, seed=SEED, sampler=sampler)
    image_after(renderer, 4)
    renderer.restart(seed=SEED + 1)
    fresh = wt.Renderer(BUILTIN_SCENES["cornell"](), SIZE, SIZE, seed=SEED + 1, sampler=sampler)
    expected = image_after(fresh, 4)
    assert np.array_equal(image_after(renderer, 4), expected)
    renderer.restart()
    assert np.array_equal(image_after(renderer, 4), expected)
