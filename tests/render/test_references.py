"""Our renderer against Mitsuba 3, per block of pixels, on every case of
wgputrace.testing.reference_cases (which says what each family of cases is for).

Each case renders once per session as independent batches (our variance per pixel from their
spread); the reference, averaged down to the case's size (exact under a box filter), brings its own
standard error. Per block and channel, Welch's t-test at Sidak's share of the family's significance;
a failure writes ours, the reference, their difference and the failing blocks under tests/failures/.
Shaders broken on purpose (2026-11-23) each failed cases here: glass Fresnel's s-polarised term
alone, GGX masking with alpha^2 halved, roulette not divided by survival, an absolute ray offset, edge
hits missed within 1e-4, and next-event shadow rays from the unmoved point (the bug this found).
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
