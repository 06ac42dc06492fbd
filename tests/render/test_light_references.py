"""Our renderer against Mitsuba 3 on the scenes lit by the environment and by point, spot and
directional lights (wgputrace/scenes/environment_lit.py, punctual.py), per block of pixels, as
tests/render/test_references.py compares the others and with its helpers: Mitsuba's `envmap`,
`constant`, `point`, `spot` and `directional` against ours (wgputrace/reference/mitsuba_scene.py
exports them).

`env_one_texel` is the environment map's direction convention seen by Mitsuba: a map black but
for one texel lights one side of a sphere, and Mitsuba must light the same side as brightly
(tests/render/test_light_closed_form.py pins the same map against a closed form).

The significance of each block test is Sidak's share of FAMILY_SIGNIFICANCE over every block,
channel and case of this module.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import pytest

from wgputrace.testing.references import assert_matches_reference, load_reference, render_batches
from wgputrace.testing.stats import sidak

pytestmark = pytest.mark.gpu

SIZE = 64
# Block sizes tested: 8x8 finds local errors, the whole image small ones spread everywhere.
BLOCKS = (8, SIZE)
# test_references.py's seed: the outcome these tests were checked with
SEED = 20261123
# Probability that this module reports a difference somewhere when there is none.
FAMILY_SIGNIFICANCE = 1e-3


@dataclass(frozen=True)
class Case:
    scene: str
    integrator: str
    batches: int
    spp: int  # per batch


# MIS on every scene; light sampling alone and BSDF sampling alone on the environments: BSDF
# sampling finds the sunny sky's sun (a few texels) too rarely for a t-test at an affordable
# count, so it is tested on the constant sky, where every escaped ray counts.
CASES = [
    Case("env_sun_spheres", "mis", batches=8, spp=32),
    Case("env_sun_spheres", "nee", batches=8, spp=32),
    Case("constant_env", "mis", batches=8, spp=32),
    Case("constant_env", "bsdf", batches=8, spp=32),
    Case("env_one_texel", "mis", batches=8, spp=16),
    Case("point_spot_directional", "mis", batches=8, spp=32),
]


BLOCK_TESTS = sum((SIZE // block) ** 2 for block in BLOCKS) * 3
PER_TEST_SIGNIFICANCE = sidak(FAMILY_SIGNIFICANCE, BLOCK_TESTS * len(CASES))


@cache
def reference(name: str):
    return load_reference(name)


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=lambda case: f"{case.scene}-{case.integrator}")
def test_matches_mitsuba_reference(gpu_context, failure_dir, case):
    ref = reference(case.scene)
    render = render_batches(
        case.scene,
        SIZE,
        batches=case.batches,
        spp=case.spp,
        seed=SEED,
        max_depth=ref.metadata["max_depth"],
        integrator=case.integrator,
    )
    assert_matches_reference(
        f"{case.scene}_{case.integrator}_vs_mitsuba",
        render,
        ref,
        failure_dir,
        blocks=BLOCKS,
        per_test_significance=PER_TEST_SIGNIFICANCE,
    )
