"""MASK cut-outs against Mitsuba 3 on `alpha_cutout` (wgputrace/scenes/alpha_cutout.py: a striped
cut-out quad between a small lamp and a wall), per block of pixels, as
tests/render/test_textures_reference.py compares textures. The camera's rays see the stripes and
the shadow rays draw them on the wall: a cut-out that only one kind of ray honours, a flipped or
shifted alpha lookup or a wrong cutoff moves or loses stripes, in the quad or in its shadow.

The significance of each block test is Sidak's share of FAMILY_SIGNIFICANCE over every block and
channel of this module.
"""

from __future__ import annotations

import pytest

from wgputrace.testing.references import STORAGE_RTOL, assert_same_expectation, load_reference, render_batches
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SCENE = "alpha_cutout"
SIZE = 64
# Block sizes tested: 8x8 finds a moved or lost stripe, the whole image small errors everywhere.
BLOCKS = (8, SIZE)
SEED = 20261203
BATCHES = 16
SPP = 32  # per batch
# Probability that this module reports a difference somewhere when there is none.
FAMILY_SIGNIFICANCE = 1e-3
BLOCK_TESTS = sum((SIZE // block) ** 2 for block in BLOCKS) * 3
PER_TEST_SIGNIFICANCE = sidak(FAMILY_SIGNIFICANCE, BLOCK_TESTS)


@pytest.mark.slow
def test_matches_mitsuba_reference(gpu_context, failure_dir):
    reference = load_reference(SCENE)
    render = render_batches(SCENE, SIZE, batches=BATCHES, spp=SPP, seed=SEED, max_depth=reference.metadata["max_depth"])
    assert render.nonfinite_samples == 0
    expected = reference.estimate.downsampled(reference.metadata["width"] // SIZE)
    assert_same_expectation(
        f"{SCENE}_vs_mitsuba",
        render.estimate,
        expected,
        expected.mean,
        STORAGE_RTOL,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=PER_TEST_SIGNIFICANCE,
    )
