"""A textured asset against Mitsuba 3: `textured_asset` (wgputrace/scenes/textured_asset.py: a panel
with base colour, metallic-roughness, normal and emission textures, per-vertex normals and texture
coordinates, on a floor its emissive marks light, under a point light), per block of pixels, as
tests/render/test_textures_reference.py compares textured quads. The export under test: Mitsuba's
`normalmap` wrapper (green flipped where our tangents' w is -1, normal_scale baked into the texels)
and an `area` emitter with a `bitmap` radiance (wgputrace/reference/mitsuba_scene.py).

Our terminator term for mapped normals, which Mitsuba lacks, is kept out of play by the scene's
lighting (see its module). The significance of each block test is Sidak's share of
FAMILY_SIGNIFICANCE over every block and channel of this module.
"""

from __future__ import annotations

import pytest

from wgputrace.testing.references import STORAGE_RTOL, assert_same_expectation, load_reference, render_batches
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SCENE = "textured_asset"
SIZE = 64
# Block sizes tested: 8x8 finds a moved texel block or bumps lit from the wrong side, the whole
# image small errors everywhere.
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
