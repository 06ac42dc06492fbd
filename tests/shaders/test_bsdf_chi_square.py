"""Chi-square goodness-of-fit of the shipped BSDF sampling (bsdf_sample) against the shipped pdf
(bsdf_pdf), both run on the GPU with random numbers from numpy: diffuse and glossy at roughness
0.01 to 1, incident angles down to grazing (cos theta = 1e-3) and from below. Glass's two delta
lobes are tested by the frequency of each choice against Fresnel and by their exact directions.

Expected counts integrate bsdf_pdf over the cells of a `HemisphereGrid`. Samples the pdf
does not cover (none for diffuse; for glossy, microfacets that reflect below the horizon) come
back invalid: a binomial test checks that bsdf_pdf integrates to the fraction of valid samples.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Glass, Glossy
from wgputrace.render.scene_records import material_records
from wgputrace.testing.bsdf_grid import (
    PDF,
    UNIT_LENGTH_TOLERANCE,
    incident_directions,
    integrate_bsdf,
    lobe_grid,
    refraction_indices,
    sample_bsdf,
    sin_theta,
)
from wgputrace.testing.oracles import UNIT_ROUNDOFF, fresnel_dielectric, relative_error
from wgputrace.testing.stats import (
    MIN_EXPECTED,
    binomial_p_value,
    chi_square,
    detectable_misallocation,
    pool_sparse_cells,
    save_histograms,
    sidak,
)

pytestmark = [pytest.mark.gpu, pytest.mark.slow]

# Each case draws its random numbers from numpy with the seed (SEED, its index).
SEED = 42026
# Probability that any test of this file fails although sampler and pdf agree, Sidak-split over
# all of them. (Within a case the chi-square and the test of invalid samples are dependent; for
# them Sidak's level exceeds Bonferroni's, valid under any dependence, by a relative 5e-4.)
SIGNIFICANCE = 1e-3
# Samples per case, chosen for power: with ~800 bins at the Sidak-corrected level, 2^20 samples
# detect with probability POWER a sampler that moves DETECTABLE_ERROR of the probability between
# two halves of the distribution (each test asserts this holds for its own bins).
SAMPLES = 2**20
DETECTABLE_ERROR = 0.02
POWER = 0.99
# Expected counts come from quadrature: its estimated error in every bin stays below this
# fraction of the bin's standard deviation sqrt(expected), so it moves no bin by more than 0.1 z.
INTEGRATION_FRACTION = 0.1
# bsdf_pdf's float32 values carry a few roundings each; their integral may exceed 1 by as much.
PDF_ROUNDINGS = 16

INCIDENT_COSINES = (1.0, 0.5, 0.1, 1e-2, 1e-3)
# One incidence from below the surface: two-sided materials must mirror it.
FROM_BELOW = -0.5
MATERIALS = [Diffuse("diffuse", color=(1, 1, 1))] + [
    Glossy(f"glossy {r}", color=(1, 1, 1), roughness=r) for r in (0.01, 0.1, 0.5, 1.0)
]
REFLECTION_CASES = [(m, cos) for m in MATERIALS for cos in (*INCIDENT_COSINES, FROM_BELOW)]

GLASS_IORS = (1.33, 1.51714, 2.4)
GLASS_CASES = [(ior, side * cos) for ior in GLASS_IORS for side in (1.0, -1.0) for cos in INCIDENT_COSINES]
# Per glass case: the reflected fraction then has a standard deviation of at most 0.0014.
GLASS_SAMPLES = 2**17

# Each reflection case runs a chi-square and a binomial test, each glass case a binomial test.
LEVEL = sidak(SIGNIFICANCE, 2 * len(REFLECTION_CASES) + len(GLASS_CASES))


def incident(cos_theta: float, rng: np.random.Generator) -> np.ndarray:
    return incident_directions(rng, np.array([cos_theta]))[0]


def error_budget(integrals: np.ndarray) -> np.ndarray:
    """Quadrature error each cell may have: its share of INTEGRATION_FRACTION of the standard
    deviation of its pooled bin."""
    expected = SAMPLES * integrals.ravel()
    bins = pool_sparse_cells(expected)
    bin_expected, bin_cells = np.bincount(bins, expected), np.bincount(bins)
    per_cell = INTEGRATION_FRACTION * np.sqrt(np.maximum(bin_expected, MIN_EXPECTED))[bins] / bin_cells[bins]
    return per_cell.reshape(integrals.shape) / SAMPLES


def case_id(case) -> str:
    first, cos_theta = case
    name = first.name if hasattr(first, "name") else f"glass {first}"
    return f"{name}, cos {cos_theta:g}"


@pytest.mark.parametrize("index", range(len(REFLECTION_CASES)), ids=[case_id(c) for c in REFLECTION_CASES])
def test_sampling_follows_pdf(gpu_context, failure_dir, index):
    material, cos_theta = REFLECTION_CASES[index]
    rng = np.random.default_rng((SEED, index))
    wi = incident(cos_theta, rng)
    records = material_records([material])
    grid = lobe_grid(material, wi)
    integrals = integrate_bsdf(gpu_context, records, wi[None], [grid], PDF, error_budget)
    cell_probability, cell_error = integrals.value[0].ravel(), integrals.error[0].ravel()
    samples = sample_bsdf(gpu_context, records, wi[None], rng.random((1, SAMPLES, 3), dtype=np.float32))[0]
    valid = samples[:, 3] > 0.0
    directions = samples[valid, :3]
    crossed = np.sign(directions[:, 2]) != np.sign(wi[2])
    assert not crossed.any(), f"{crossed.sum()} samples leave a two-sided surface on the side opposite wi {wi}"

    # The pdf's integral is known to within the sum of the cells' quadrature errors: the invalid
    # samples must fit some fraction 1 - integral in that interval (the p-value is the largest
    # over it), and the integral may not exceed 1 by more.
    mass, mass_error = cell_probability.sum(), cell_error.sum() + PDF_ROUNDINGS * UNIT_ROUNDOFF
    assert mass <= 1.0 + mass_error, f"bsdf_pdf integrates to {mass:.7f} > 1 for wi {wi} (+- {mass_error:.2g})"
    invalid = SAMPLES - valid.sum()
    closest = np.clip(invalid / SAMPLES, max(1.0 - mass - mass_error, 0.0), max(1.0 - mass + mass_error, 0.0))
    invalid_p = binomial_p_value(invalid, SAMPLES, closest)
    assert invalid_p >= LEVEL, (
        f"{invalid} of {SAMPLES} samples invalid for wi {wi}, where the pdf, integrating to {mass:.7f} "
        f"+- {mass_error:.2g}, leaves {SAMPLES * (1 - mass):.1f}: p = {invalid_p:.3g} < {LEVEL:.3g}"
    )

    # Valid samples, given their number, fall into cells with probabilities integral / mass.
    observed = grid.histogram(directions).ravel()
    expected = valid.sum() * cell_probability / mass
    result = chi_square(observed, expected)
    bin_error = valid.sum() * np.bincount(result.pool_index, cell_error) / mass
    bin_expected = np.bincount(result.pool_index, expected)
    worst = np.argmax(bin_error / np.sqrt(bin_expected))
    assert bin_error[worst] <= INTEGRATION_FRACTION * np.sqrt(bin_expected[worst]), (
        f"quadrature error {bin_error[worst]:.3g} of bin {worst} (expects {bin_expected[worst]:.1f}) for wi {wi}: "
        "refine the grid (bsdf_grid.MAX_REFINEMENTS) before trusting the test"
    )
    detectable = detectable_misallocation(SAMPLES, result.dof, LEVEL, POWER)
    assert detectable <= DETECTABLE_ERROR, f"{SAMPLES} samples in {result.bins} bins detect only {detectable:.3f}"
    path = failure_dir / f"chi_square_{case_id(REFLECTION_CASES[index]).replace(' ', '_').replace(',', '')}.png"
    if result.p_value < LEVEL:
        save_histograms(path, observed.reshape(grid.cells), expected.reshape(grid.cells))
    assert result.p_value >= LEVEL, (
        f"{material.name} at wi {wi}: chi-square {result.statistic:.1f} with {result.dof} degrees of freedom, "
        f"p = {result.p_value:.3g} < {LEVEL:.3g} ({result.pooled_cells} sparse cells pooled); histograms in "
        f"{path} (rows: cos theta from 0 at the top to 1; columns: azimuth from opposite the mirror direction)"
    )


@pytest.fixture(scope="module")
def glass_samples(gpu_context):
    """(wi (cases, 3), samples (cases, GLASS_SAMPLES, 4)) for every GLASS_CASE, in one dispatch."""
    rng = np.random.default_rng((SEED, len(REFLECTION_CASES)))
    wi = np.stack([incident(cos_theta, rng) for _, cos_theta in GLASS_CASES])
    records = material_records([Glass(f"glass {ior}", color=(1, 1, 1), ior=ior) for ior, _ in GLASS_CASES])
    u = rng.random((len(GLASS_CASES), GLASS_SAMPLES, 3), dtype=np.float32)
    return wi, sample_bsdf(gpu_context, records, wi, u)


@pytest.mark.parametrize("index", range(len(GLASS_CASES)), ids=[case_id(c) for c in GLASS_CASES])
def test_glass_chooses_lobes_by_fresnel_in_exact_directions(glass_samples, index):
    ior = GLASS_CASES[index][0]
    wi_all, samples_all = glass_samples
    wi, samples = wi_all[index], samples_all[index]
    directions = samples[:, :3]
    assert np.all(samples[:, 3] > 0.0), "glass failed to sample a direction"
    reflected = np.sign(directions[:, 2]) == np.sign(wi[2])
    mirror = wi * np.array([-1, -1, 1], np.float32)
    assert np.all(directions[reflected] == mirror), f"a reflected direction is not the mirror {mirror} of wi {wi}"

    eta_i, eta_t = refraction_indices(np.array([ior]), wi[None])
    reflectance = float(fresnel_dielectric(wi[None, 2], eta_i, eta_t)[0])
    p_value = binomial_p_value(reflected.sum(), GLASS_SAMPLES, reflectance)
    assert p_value >= LEVEL, (
        f"glass {ior} at wi {wi}: {reflected.mean():.5f} of samples reflect, Fresnel says {reflectance:.5f} "
        f"(p = {p_value:.3g} < {LEVEL:.3g})"
    )
    if reflected.all():
        return
    # refraction is deterministic: one direction, across the normal, obeying Snell's law
    refracted = np.unique(directions[~reflected], axis=0)
    assert len(refracted) == 1, f"glass {ior} at wi {wi} refracts into {len(refracted)} different directions"
    wo = refracted[:1].astype(np.float64)
    snell = relative_error(eta_t * sin_theta(wo), eta_i * sin_theta(wi[None]))[0]
    across = np.sign(wo[0, 2]) == -np.sign(wi[2]) and np.dot(wo[0, :2], wi[:2]) <= 0.0
    assert across and snell <= 4 * UNIT_LENGTH_TOLERANCE, f"refracted {wo[0]} for wi {wi}: Snell off by {snell:.3g}"
