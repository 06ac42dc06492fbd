"""Issue 14's materials and assets against Mitsuba 3, per block of pixels, with the helpers
tests/render/test_references.py compares the other scenes with. The pointwise tests pin each piece
(tests/shaders/test_principled.py the BSDF, tests/render/test_textures.py the lookup,
tests/render/test_alpha_emission.py the cut-outs); these pin them inside the path tracer and
against an independent renderer:

- `principled_spheres` (wgputrace/scenes/principled.py: metallic 0 to 1, roughness 0.1 to 1, in the
  emitting room): the two-sided wrapper, light sampling and MIS weights that use its pdf.
- `textured_quads` (wgputrace/scenes/textured.py: a marked sRGB checkerboard repeating past [0, 1],
  a metallic-roughness texture mirrored and transformed): orientation, sRGB decoding, wrap modes,
  KHR_texture_transform against Mitsuba's `bitmap`.
- `alpha_cutout` (wgputrace/scenes/alpha_cutout.py: a striped cut-out quad between a small lamp and
  a wall): camera rays see the stripes and shadow rays draw them on the wall; a cut-out that only
  one kind of ray honours, a flipped or shifted alpha lookup or a wrong cutoff moves or loses stripes.
- `textured_asset` (wgputrace/scenes/textured_asset.py: a panel with base colour, metallic-roughness,
  normal and emission textures, per-vertex normals and texture coordinates, on a floor its emissive
  marks light, under a point light): Mitsuba's `normalmap` wrapper (green flipped where our
  tangents' w is -1, normal_scale baked into the texels) and an `area` emitter with a `bitmap`
  radiance (wgputrace/reference/mitsuba_scene.py). Our terminator term for mapped normals, which
  Mitsuba lacks, is kept out of play by the scene's lighting (see its module).
- `alpha_blend` (alpha_cutout.py: the quad BLEND, its alpha ramping across it): stochastic
  transparency for camera and shadow rays against its expectation, Mitsuba's `mask` of that alpha.

Block sizes: 8x8 finds a moved texel block, stripe or lobe, the whole image small errors spread
everywhere. The significance of each block test is Sidak's share of FAMILY_SIGNIFICANCE over every
block, channel and scene of this module.
"""

from __future__ import annotations

import pytest

from wgputrace.testing.references import assert_matches_reference, load_reference, render_batches
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

# scene: the seed of its batches (different seeds, so the scenes' noise is independent)
SCENES = {
    "principled_spheres": 20261201,
    "textured_quads": 20261202,
    "alpha_cutout": 20261203,
    "textured_asset": 20261204,
    "principled_transmission": 20261209,
    "alpha_blend": 20261206,
}
SIZE = 64
BLOCKS = (8, SIZE)
BATCHES = 16
SPP = 32  # per batch
# Probability that this module reports a difference somewhere when there is none.
FAMILY_SIGNIFICANCE = 1e-3
BLOCK_TESTS = sum((SIZE // block) ** 2 for block in BLOCKS) * 3 * len(SCENES)
PER_TEST_SIGNIFICANCE = sidak(FAMILY_SIGNIFICANCE, BLOCK_TESTS)


@pytest.mark.slow
@pytest.mark.parametrize("scene", SCENES)
def test_matches_mitsuba_reference(gpu_context, failure_dir, scene):
    reference = load_reference(scene)
    render = render_batches(
        scene, SIZE, batches=BATCHES, spp=SPP, seed=SCENES[scene], max_depth=reference.metadata["max_depth"]
    )
    assert_matches_reference(
        f"{scene}_vs_mitsuba",
        render,
        reference,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=PER_TEST_SIGNIFICANCE,
    )
