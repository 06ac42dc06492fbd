"""Our renderer against Mitsuba 3, per block of pixels, on every case of
wgputrace.testing.reference_cases (which says what each family of cases is for).

Each case renders once per session as independent batches; our variance per pixel comes from the
spread of the batches. The reference (128x128, averaged down to the case's size, which a box
filter makes exact) brings its own standard error. Per block and channel, Welch's t-test asks
whether the two expectations differ, at Sidak's share of the family's significance. A failure
writes ours, the reference, their difference and a map of the failing blocks under tests/failures/.

What the path tracer's cases catch, each shader broken on purpose in a copy of the tree (2026-11-23):
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

One module for every family: the comparison is the same for all of them, and the registry, not
the module, says what differs (size, samples, seed, integrator, overrides, blocks, family).
"""

from __future__ import annotations

from functools import cache
from operator import attrgetter

import numpy as np
import pytest

from wgputrace.testing.image_statistics import Estimate
from wgputrace.testing.reference_cases import CASES, REFERENCE_SIZE, REFERENCES, ReferenceCase, paired_case
from wgputrace.testing.references import (
    BatchedRender,
    Reference,
    assert_matches_reference,
    assert_same_expectation,
    block_test_significance,
    load_reference,
    reference_dir,
    render_case,
)

REFERENCES_MAX_BYTES = 5 * 1024 * 1024
# The scaled boxes compute every hit point and direction from coordinates 1e4 times larger or
# smaller: float32 rounds them differently (a few steps of 2^-24 per bounce), which moves the
# expectation by far less than this fraction; the same bound as test_closed_form's EXACT_RTOL.
SCALED_RTOL = 1e-5

case_names = attrgetter("name")


@cache
def reference(name: str) -> Reference:
    return load_reference(name)


@cache
def rendered(case: ReferenceCase) -> BatchedRender:
    """Once per session: the paired comparison reuses the renders of its two cases."""
    return render_case(case)


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=case_names)
def test_matches_mitsuba_reference(gpu_context, failure_dir, case):
    assert_matches_reference(
        f"{case.name}_vs_mitsuba",
        rendered(case),
        reference(case.reference),
        failure_dir,
        blocks=case.blocks,
        per_test_significance=block_test_significance(case),
    )


@pytest.mark.slow
@pytest.mark.parametrize("case", [case for case in CASES if case.same_paths_as], ids=case_names)
def test_scaled_cornell_box_gives_the_same_image(gpu_context, failure_dir, case):
    """Paired per batch with the unscaled box (same seed, so mostly the same paths): the batch
    differences have expectation zero, and their spread holds only the paths that went differently,
    so this sees far smaller differences than a comparison of independent images."""
    scaled_batches = rendered(case).batches.astype(np.float64)
    unscaled_batches = rendered(paired_case(case)).batches[: len(scaled_batches)].astype(np.float64)
    difference = Estimate.from_batches(scaled_batches - unscaled_batches)
    zero = Estimate(np.zeros_like(difference.mean), np.zeros_like(difference.mean), np.inf)
    unscaled = unscaled_batches.mean(axis=0)
    assert_same_expectation(
        f"{case.scene}_vs_{case.same_paths_as}",
        difference,
        zero,
        unscaled,
        SCALED_RTOL,
        failure_dir,
        blocks=case.blocks,
        per_test_significance=block_test_significance(case),
    )


def test_cases_are_named_once_and_every_reference_is_some_cases():
    assert len({case.name for case in CASES}) == len(CASES)  # the test ids
    assert {case.reference for case in CASES} == set(REFERENCES)
    assert all(REFERENCE_SIZE % case.size == 0 for case in CASES)


def test_references_are_small_and_match_their_settings():
    paths = sorted(reference_dir().glob("*.npz"))
    total = sum(path.stat().st_size for path in paths)
    assert total < REFERENCES_MAX_BYTES, f"references take {total:,} bytes, more than {REFERENCES_MAX_BYTES:,}"
    assert {path.stem for path in paths} == set(REFERENCES)
    for path in paths:
        ref = reference(path.stem)
        metadata = ref.metadata
        settings = REFERENCES[path.stem]
        assert metadata["scene"] == path.stem
        assert (metadata["max_depth"], metadata["spp"], metadata["passes"]) == (
            settings.max_depth,
            settings.spp,
            settings.passes,
        )
        assert metadata["width"] == metadata["height"] == REFERENCE_SIZE
        assert ref.estimate.mean.shape == (metadata["height"], metadata["width"], 3)
        assert np.isfinite(ref.estimate.mean).all() and np.isfinite(ref.estimate.variance).all()
