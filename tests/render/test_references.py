"""Our renderer against Mitsuba 3 on the test scenes (wgputrace/scenes), per block of pixels.

Each scene renders once per session at SIZE x SIZE as K independent batches; our variance per
pixel comes from the spread of the batches. The reference (128x128, averaged down to SIZE x SIZE,
which a box filter makes exact) brings its own standard error. Per block (8x8, and the whole
image) and channel, Welch's t-test asks whether the two expectations differ; the significance of
each test is Sidak's share of FAMILY_SIGNIFICANCE over every block, channel and scene of this
module. A failure writes ours, the reference, their difference and a map of the failing blocks
under tests/failures/.

What it catches, each shader broken on purpose in a copy of the tree (2026-11-23):
- glass Fresnel as the s-polarised term alone: glass_grazing (59 of 192 8x8 blocks), cornell
  and both scaled boxes (3 to 6 blocks, the glass sphere);
- GGX masking G1 with alpha^2 halved: glossy_spheres (49 blocks);
- Russian roulette without dividing by the survival probability: cornell, tiny_light,
  glass_grazing, axis_boxes and the scaled boxes (66 to 165 blocks), not glossy_spheres or slivers;
- an absolute ray offset (1e-5) instead of a relative one: cornell_1e-4 against Mitsuba (71
  blocks) and both scaled boxes against the unscaled one;
- a triangle test that misses hits within 1e-4 (barycentric) of an edge: slivers, red over the
  whole image (z = 7.9: the hidden lamp seen through the gaps; no single block shows it);
- the shadow ray of next-event estimation measured from the unmoved point (the bug this found):
  tiny_light (178 blocks), cornell (70; the ceiling beside the lamp a third too dark, z -16) and
  the scaled boxes (42), and test_light_near_surface.py.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, partial

import numpy as np
import pytest

from wgputrace.testing.image_statistics import Estimate
from wgputrace.testing.references import (
    STORAGE_RTOL,
    BatchedRender,
    assert_matches_reference,
    assert_same_expectation,
    load_reference,
    reference_dir,
    render_batches,
)
from wgputrace.testing.stats import sidak

SIZE = 64
# Block sizes tested: 8x8 finds local errors, the whole image small ones spread everywhere (a rare
# leak through the slivers adds too little to any one block to stand out of its noise).
BLOCKS = (8, SIZE)
SEED = 20261123
# Probability that this module reports a difference somewhere when there is none.
FAMILY_SIGNIFICANCE = 1e-3
REFERENCES_MAX_BYTES = 5 * 1024 * 1024
# The scaled boxes compute every hit point and direction from coordinates 1e4 times larger or
# smaller: float32 rounds them differently (a few steps of 2^-24 per bounce), which moves the
# expectation by far less than this fraction; the same bound as test_closed_form's EXACT_RTOL.
SCALED_RTOL = 1e-5


# Where mis finds much of the light only in rare paths (the caustic's light reaching the floor
# through the glass, a small lamp after two glossy bounces), the blocks' means at these sample
# counts are heavy-tailed: typical runs fall 20 to 40% short on some 8x8 blocks, which a t-test
# reads as a difference. Larger blocks pool enough paths; at 32x32 a 3 to 5% error still shows.
HEAVY_TAILED_BLOCKS = (32, SIZE)


@dataclass(frozen=True)
class Case:
    scene: str
    reference: str
    batches: int
    spp: int  # per batch
    blocks: tuple[int, ...] = BLOCKS


# Sample counts: this module with the other reference-related tests took 100 s (172 s of CPU) on
# the 2-core lavapipe machine; the budget is about four minutes.
CASES = {
    case.scene: case
    for case in (
        Case("cornell", "cornell", batches=16, spp=32),
        Case("tiny_light", "tiny_light", batches=16, spp=32),
        Case("glass_grazing", "glass_grazing", batches=16, spp=32),
        Case("glossy_spheres", "glossy_spheres", batches=16, spp=32),
        Case("slivers", "slivers", batches=16, spp=16),
        Case("axis_boxes", "axis_boxes", batches=16, spp=24),
        # scenes that break path tracers (issue 18): their light comes in rare, bright paths
        Case("door_ajar", "door_ajar", batches=16, spp=16),
        Case("caustic", "caustic", batches=16, spp=32, blocks=HEAVY_TAILED_BLOCKS),
        Case("glossy_through_glossy", "glossy_through_glossy", batches=16, spp=32, blocks=HEAVY_TAILED_BLOCKS),
        # the same box scaled, camera included: the same image, tested against the same reference
        # and, sample for sample, against the unscaled box's first batches (same seed)
        Case("cornell_1e-4", "cornell", batches=8, spp=32),
        Case("cornell_1e4", "cornell", batches=8, spp=32),
    )
}
SCALED = ("cornell_1e-4", "cornell_1e4")
UNSCALED = "cornell"
# The other direct-light strategies must converge to the same picture as MIS (the CASES above).
# BSDF sampling alone on the tiny light is left out: a lamp that small is hit so rarely that its
# estimates are too heavy-tailed for a t-test at any affordable sample count.
# Bidirectional path tracing has its own module (tests/render/test_bdpt_references.py).
INTEGRATOR_CASES = {("cornell", "bsdf"): 32, ("cornell", "nee"): 32, ("tiny_light", "nee"): 32}
INTEGRATOR_BATCHES = 8

BLOCK_TESTS = sum((SIZE // block) ** 2 for block in BLOCKS) * 3
PER_TEST_SIGNIFICANCE = sidak(FAMILY_SIGNIFICANCE, BLOCK_TESTS * (len(CASES) + len(SCALED) + len(INTEGRATOR_CASES)))
same_expectation = partial(assert_same_expectation, blocks=BLOCKS, per_test_significance=PER_TEST_SIGNIFICANCE)


@cache
def reference(name: str):
    return load_reference(name)


@cache
def rendered(scene: str) -> BatchedRender:
    case = CASES[scene]
    max_depth = reference(case.reference).metadata["max_depth"]
    return render_batches(scene, SIZE, batches=case.batches, spp=case.spp, seed=SEED, max_depth=max_depth)


@pytest.mark.slow
@pytest.mark.parametrize("scene", list(CASES))
def test_matches_mitsuba_reference(gpu_context, failure_dir, scene):
    case = CASES[scene]
    ours = rendered(scene).estimate
    ref = reference(case.reference)
    expected = ref.estimate.downsampled(ref.metadata["width"] // SIZE)
    same_expectation(
        f"{scene}_vs_mitsuba", ours, expected, expected.mean, STORAGE_RTOL, failure_dir, blocks=case.blocks
    )


@pytest.mark.slow
@pytest.mark.parametrize("scene", list(CASES))
def test_no_nan_or_infinity(gpu_context, scene):
    render = rendered(scene)
    assert render.nonfinite_samples == 0, f"{scene}: {render.nonfinite_samples} samples were NaN or infinite"
    assert np.isfinite(render.batches).all()


@pytest.mark.slow
@pytest.mark.parametrize("scaled", SCALED)
def test_scaled_cornell_box_gives_the_same_image(gpu_context, failure_dir, scaled):
    """Paired per batch with the unscaled box (same seed, so mostly the same paths): the batch
    differences have expectation zero, and their spread holds only the paths that went differently,
    so this sees far smaller differences than a comparison of independent images."""
    scaled_batches = rendered(scaled).batches.astype(np.float64)
    unscaled_batches = rendered(UNSCALED).batches[: len(scaled_batches)].astype(np.float64)
    difference = Estimate.from_batches(scaled_batches - unscaled_batches)
    zero = Estimate(np.zeros_like(difference.mean), np.zeros_like(difference.mean), np.inf)
    unscaled = unscaled_batches.mean(axis=0)
    same_expectation(f"{scaled}_vs_{UNSCALED}", difference, zero, unscaled, SCALED_RTOL, failure_dir)


def test_references_are_small_and_match_their_settings():
    paths = sorted(reference_dir().glob("*.npz"))
    total = sum(path.stat().st_size for path in paths)
    assert total < REFERENCES_MAX_BYTES, f"references take {total:,} bytes, more than {REFERENCES_MAX_BYTES:,}"
    # every reference file is some test's
    from tests.render.test_light_references import CASES as LIGHT_CASES
    from tests.render.test_material_references import SCENES as MATERIAL_SCENES
    from tests.render.test_shading_normal_references import SCENES as SHADING_NORMAL_SCENES

    used = {case.reference for case in CASES.values()} | {case.scene for case in LIGHT_CASES}
    used |= set(MATERIAL_SCENES) | set(SHADING_NORMAL_SCENES)
    assert {path.stem for path in paths} == used
    for path in paths:
        ref = reference(path.stem)
        metadata = ref.metadata
        assert metadata["scene"] == path.stem
        assert ref.estimate.mean.shape == (metadata["height"], metadata["width"], 3)
        assert metadata["width"] % SIZE == 0 and metadata["height"] == metadata["width"]
        assert np.isfinite(ref.estimate.mean).all() and np.isfinite(ref.estimate.variance).all()


@pytest.mark.slow
@pytest.mark.parametrize("scene, integrator", list(INTEGRATOR_CASES))
def test_each_integrator_matches_mitsuba_reference(gpu_context, failure_dir, scene, integrator):
    ref = reference(CASES[scene].reference)
    render = render_batches(
        scene,
        SIZE,
        batches=INTEGRATOR_BATCHES,
        spp=INTEGRATOR_CASES[scene, integrator],
        seed=SEED,
        max_depth=ref.metadata["max_depth"],
        integrator=integrator,
    )
    assert_matches_reference(
        f"{scene}_{integrator}_vs_mitsuba",
        render,
        ref,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=PER_TEST_SIGNIFICANCE,
    )
