"""Textures against Mitsuba 3 on `textured_quads` (wgputrace/scenes/textured.py: a marked sRGB
checkerboard repeating past [0, 1], a metallic-roughness texture mirrored and transformed), per
block of pixels, as tests/render/test_principled_reference.py compares the untextured material.
tests/render/test_textures.py pins the lookup pointwise; this pins the conventions (orientation,
sRGB decoding, wrap modes, KHR_texture_transform) against an independent renderer's `bitmap`.

The significance of each block test is Sidak's share of FAMILY_SIGNIFICANCE over every block and
channel of this module.
"""

from __future__ import annotations

import pytest

from wgputrace.testing.references import STORAGE_RTOL, assert_same_expectation, load_reference, render_batches
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SCENE = "textured_quads"
SIZE = 64
# Block sizes tested: 8x8 finds a moved or recoloured texel block, the whole image small errors everywhere.
BLOCKS = (8, SIZE)
SEED = 20261202
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
