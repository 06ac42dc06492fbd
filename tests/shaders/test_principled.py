"""The principled material (`Principled`, WGSL `principled_eval`, `principled_pdf`, `principled_sample`)
on the GPU: eval and pdf against Mitsuba 3's `principled` at random directions (FIXTURE, written by
the make_principled_fixture script), chi-square tests of its sampling against its pdf over the
parameter range (with transmission on a grid of both hemispheres; with the clearcoat and sheen
lobes; anisotropic), white furnaces (the integral of
its eval; Mitsuba's own), and finite samples at the extremes of every parameter and at grazing angles.

We reproduce Mitsuba's model (the lead's decision), which at metallic 0 and base colour 1 reflects
more than it receives: its Disney diffuse lobe is weighted by 1 - metallic, not by what the specular
layer leaves, and its retro-reflection grows with roughness (up to 1.584 at cos 0.01, roughness 1).
So the furnace holds ours to Mitsuba's own (MITSUBA_FURNACE, from the make_principled_furnace
script), and to at most 1 wherever Mitsuba's is."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgputrace import Glossy, Principled
from wgputrace.render.scene_records import material_records
from wgputrace.scene import MaterialError
from wgputrace.scene.materials.principled import eta_from_specular
from wgputrace.testing.bsdf_grid import (
    EVAL,
    GRID_CELLS,
    PDF,
    Axis,
    HemisphereGrid,
    evaluate_bsdf,
    incident_directions,
    integrate_bsdf,
    lobe_grid,
    sample_bsdf,
)
from wgputrace.testing.oracles import UNIT_ROUNDOFF
from wgputrace.testing.stats import MIN_EXPECTED, chi_square, sidak, z_limit

pytestmark = pytest.mark.gpu

# the clearcoat's, sheen's and anisotropy's parameters, columns of FIXTURE
LOBE_PARAMETERS = ("clearcoat", "clearcoat_gloss", "sheen", "sheen_tint", "anisotropic")
FIXTURE = Path(__file__).parent / "data" / "principled_mitsuba.npz"
MITSUBA_FURNACE = Path(__file__).parent / "data" / "principled_furnace_mitsuba.npz"
# Samples per case of the furnace grid: a standard error of ~0.003 against Mitsuba's ~0.0005.
FURNACE_SAMPLES = 2**16
SEED = 20261201
# Mitsuba computes in float32 too, with other roundings (and its own normalize): a few dozen ulps.
MITSUBA_RTOL = 2e-5
# Values far below the lobe's scale differ by roundings of the large terms they sum with.
MITSUBA_ATOL = 1e-6

# Samples per chi-square case: ~300 per cell on the 20 x 40 grid.
SAMPLES = 2**18
# Probability that any statistical test of this file fails by chance though the code is right.
SIGNIFICANCE = 1e-3
ROUGHNESS = (0.05, 0.3, 1.0)
METALLIC = (0.0, 0.5, 1.0)
# down to grazing, and from below the surface: a two-sided material mirrors wi there
INCIDENT_COSINES = (0.9, 0.2, 0.01, -0.5)
# with transmission below is inside: from there light reflects (totally beyond the critical angle,
# cos 0.75 at eta 1.5) or refracts out
SPEC_TRANS = (0.5, 1.0)
SPEC_TRANS_METALLIC = 0.25
SPEC_TRANS_COSINES = (0.9, 0.2, -0.5, -0.9)
# (roughness, metallic, spec_trans, cos theta_i)
# the clearcoat (rough and glossy, over rough and smooth GGX, from near normal to grazing) and the
# sheen (tinted, on a half metallic base), as (parameter, value) pairs
# and anisotropy (the most Mitsuba has, over both GGX lobes; wi at random azimuths about the tangent)
LOBES = (
    (("clearcoat", 1.0), ("clearcoat_gloss", 0.0)),
    (("clearcoat", 0.5), ("clearcoat_gloss", 0.9)),
    (("sheen", 1.0), ("sheen_tint", 0.5)),
    (("anisotropic", 1.0),),
)
ANISOTROPIC = LOBES[3]
LOBE_COSINES = (0.9, 0.2)
# (roughness, metallic, spec_trans, cos theta_i, lobes)
SAMPLING_CASES = [(r, m, 0.0, c, ()) for r in ROUGHNESS for m in METALLIC for c in INCIDENT_COSINES] + [
    (r, SPEC_TRANS_METALLIC, t, c, ()) for r in ROUGHNESS for t in SPEC_TRANS for c in SPEC_TRANS_COSINES
]
SAMPLING_CASES += [(r, 0.5, 0.0, c, lobes) for r in (0.05, 1.0) for lobes in LOBES for c in LOBE_COSINES]
SAMPLING_CASES += [(0.3, 0.0, 0.5, 0.9, LOBES[0] + LOBES[2])]
SAMPLING_CASES += [(0.3, SPEC_TRANS_METALLIC, 1.0, c, ANISOTROPIC) for c in (0.9, -0.5)]
SAMPLING_CASES += [(r, 1.0, 0.0, 0.01, ANISOTROPIC) for r in (0.05, 0.5)]
# (roughness, metallic, lobes)
FURNACE_CASES = [(r, m, ()) for r in (0.05, 0.5, 1.0) for m in (0.0, 0.5, 1.0)]
FURNACE_CASES += [(r, m, lobes) for r in (0.05, 1.0) for m in (0.0, 1.0) for lobes in LOBES]
FURNACE_COSINE = 0.5
LEVEL = sidak(SIGNIFICANCE, len(SAMPLING_CASES) + len(FURNACE_CASES))
# Quadrature of the pdf and eval over the grid moves no cell's expected count by more than this
# fraction of its standard deviation.
INTEGRATION_FRACTION = 0.1


def white(roughness: float, metallic: float, spec_trans: float = 0.0, lobes=()) -> Principled:
    return Principled(
        f"principled r{roughness:g} m{metallic:g} t{spec_trans:g}" + "".join(f" {k} {v:g}" for k, v in lobes),
        (1, 1, 1),
        metallic,
        roughness,
        spec_trans=spec_trans,
        **dict(lobes),
    )


def case_id(case) -> str:
    *numbers, lobes = case
    names = ("r", "m", "t", "cos")[: len(numbers)] if len(numbers) == 4 else ("r", "m")
    return " ".join(f"{n}{v:g}" for n, v in zip(names, numbers, strict=True)) + "".join(f" {k}{v:g}" for k, v in lobes)


def ggx_grid(material: Principled, wi: np.ndarray):
    """The bsdf_grid cells of a GGX lobe of the principled material's alpha, or of its clearcoat's
    where that is narrower (crowded around the mirror direction); its diffuse lobe and sheen are
    smooth over any grid."""
    alpha = max(0.001, material.roughness**2)
    if material.clearcoat > 0:
        alpha = min(alpha, 0.1 + (0.001 - 0.1) * material.clearcoat_gloss)
    return lobe_grid(Glossy("grid", roughness=alpha), wi)


def refraction_grid(material: Principled, wi: np.ndarray) -> HemisphereGrid:
    """Cells on the side opposite wi crowding around the smooth refraction of wi (uniform past
    the critical angle), at the lobe's scale widened by the relative index of refraction."""
    alpha = max(0.001, material.roughness**2)
    eta = material.eta if wi[2] > 0 else 1.0 / material.eta
    sin_i = float(np.hypot(wi[0], wi[1]))
    phi_r = float(np.arctan2(-wi[1], -wi[0]))
    rows = GRID_CELLS[0]
    sin_t = sin_i / eta
    if sin_t >= 1.0:
        return HemisphereGrid(-np.sign(wi[2]), Axis(0.0, 1.0), phi_r, np.full(rows, np.inf))
    cos_t = np.sqrt(1.0 - sin_t**2)
    spread = 2.0 * alpha * max(eta, 1.0 / eta)
    cos_theta = Axis(0.0, 1.0, cos_t, spread * (sin_t + alpha))
    edges = cos_theta.edges(rows)
    c = 0.5 * (edges[:-1] + edges[1:])
    phi_width = spread * (c + cos_t) / np.sqrt(1.0 - c**2)
    return HemisphereGrid(-np.sign(wi[2]), cos_theta, phi_r, np.where(phi_width < np.pi, phi_width, np.inf))


def quadrature_budget(integrals: np.ndarray) -> np.ndarray:
    return INTEGRATION_FRACTION * np.sqrt(np.maximum(SAMPLES * integrals, MIN_EXPECTED)) / SAMPLES


def test_eval_and_pdf_match_mitsuba(gpu_context):
    fixture = np.load(FIXTURE)
    materials = [
        Principled(
            f"m{i}",
            tuple(fixture["base_color"][i]),
            *(float(fixture[k][i]) for k in ("metallic", "roughness", "eta")),
            spec_trans=float(fixture["spec_trans"][i]),
            **{name: float(fixture[name][i]) for name in LOBE_PARAMETERS},
        )
        for i in range(len(fixture["metallic"]))
    ]
    cases, directions = fixture["wi"].shape[:2]
    # one case per pair: evaluate_bsdf takes wi per case
    records = material_records(materials)[np.repeat(np.arange(cases), directions)]
    out = evaluate_bsdf(
        gpu_context, records, fixture["wi"].reshape(-1, 3), fixture["wo"].reshape(-1, 3), np.arange(cases * directions)
    )
    np.testing.assert_allclose(out[:, :3], fixture["eval"].reshape(-1, 3), rtol=MITSUBA_RTOL, atol=MITSUBA_ATOL)
    np.testing.assert_allclose(out[:, PDF], fixture["pdf"].reshape(-1), rtol=MITSUBA_RTOL, atol=MITSUBA_ATOL)


@pytest.mark.slow
@pytest.mark.parametrize("case", SAMPLING_CASES, ids=[case_id(case) for case in SAMPLING_CASES])
def test_sampling_follows_pdf(gpu_context, case):
    roughness, metallic, spec_trans, cos_theta, lobes = case
    rng = np.random.default_rng((SEED, SAMPLING_CASES.index(case)))
    material = white(roughness, metallic, spec_trans, lobes)
    wi = incident_directions(rng, np.array([cos_theta]))
    records = material_records([material])
    # wi's side (reflection), and the other side where the material transmits
    reflected = ggx_grid(material, wi[0])
    grids = [reflected] + ([refraction_grid(material, wi[0])] if spec_trans > 0 else [])
    integrals = integrate_bsdf(
        gpu_context, records[[0] * len(grids)], wi[[0] * len(grids)], grids, PDF, quadrature_budget
    )
    probability = integrals.value.ravel()
    budget = quadrature_budget(probability)
    assert np.all(integrals.error.ravel() <= budget), "refine the grid (bsdf_grid.MAX_REFINEMENTS) first"
    samples = sample_bsdf(gpu_context, records, wi, rng.random((1, SAMPLES, 3), dtype=np.float32))[0]
    valid = samples[:, 3] > 0.0
    crossed = np.sign(samples[:, 2]) != np.sign(wi[0, 2])
    if spec_trans == 0:
        assert not (valid & crossed).any(), (
            f"{(valid & crossed).sum()} samples leave the two-sided surface on the side opposite wi"
        )
    mass = probability.sum()
    assert mass <= 1.0 + budget.sum(), f"pdf integrates to {mass:.6f} > 1"
    observed = np.concatenate(
        [grid.histogram(samples[valid & (crossed == (grid is not reflected)), :3]).ravel() for grid in grids]
    )
    result = chi_square(observed, valid.sum() * probability / mass)
    assert result.p_value >= LEVEL, (
        f"{material.name} at wi {wi[0]}: chi-square {result.statistic:.1f}, {result.dof} dof, p = {result.p_value:.3g}"
    )


@pytest.mark.slow
@pytest.mark.parametrize("case", FURNACE_CASES, ids=[case_id(case) for case in FURNACE_CASES])
def test_white_furnace_keeps_the_integral_of_eval(gpu_context, case):
    rng = np.random.default_rng((SEED, len(SAMPLING_CASES) + FURNACE_CASES.index(case)))
    roughness, metallic, lobes = case
    material = white(roughness, metallic, lobes=lobes)
    wi = incident_directions(rng, np.array([FURNACE_COSINE]))
    records = material_records([material])
    albedo = integrate_bsdf(gpu_context, records, wi, [ggx_grid(material, wi[0])], EVAL, quadrature_budget)
    kept = albedo.value.sum()
    # Mitsuba's clearcoat adds to the base without taking what it reflects from it: a white metal
    # under a clearcoat keeps up to ~1.013 (cos 0.5, roughness 0.05), so only the bare metal is held to 1
    if material.metallic == 1.0 and material.clearcoat == 0.0:
        assert kept <= 1.0 + albedo.error.sum() + 16 * UNIT_ROUNDOFF, f"{material.name} keeps {kept:.6f} > 1"
    samples = sample_bsdf(gpu_context, records, wi, rng.random((1, SAMPLES, 3), dtype=np.float32))[0]
    valid = samples[:, 3] > 0.0
    directions = samples[valid, :3]
    weights = evaluate_bsdf(gpu_context, records, wi, directions, np.zeros(len(directions), np.int64))
    per_sample = np.zeros(SAMPLES)
    per_sample[valid] = weights[:, 0] / weights[:, PDF]
    estimate, error = per_sample.mean(), per_sample.std() / np.sqrt(SAMPLES)
    assert abs(estimate - kept) <= z_limit(LEVEL) * error + albedo.error.sum(), (
        f"{material.name}: sampled weights average {estimate:.5f} +- {error:.2g}, the integral of eval is {kept:.5f}"
    )


@pytest.mark.slow
def test_white_furnace_is_mitsubas(gpu_context):
    """Mean sample weight (eval / pdf) of a white surface for light from outside, against Mitsuba's
    on its grid (with and without a clearcoat or a sheen): equal within both estimators' errors
    everywhere, and at most 1 wherever Mitsuba's is."""
    fixture = np.load(MITSUBA_FURNACE)
    axes = [fixture[name] for name in ("roughness", "metallic", "spec_trans", "cos_theta")]
    # the last axis: no optional lobe, then each row of the fixture's lobe parameters
    lobes = [{}] + [
        dict(zip(names.tolist(), values.tolist(), strict=True))
        for names, values in zip(fixture["lobe_names"], fixture["lobes"], strict=True)
    ]
    grid = [
        (index, (*(float(axis[i]) for axis, i in zip(axes, index, strict=False)), lobes[index[-1]]))
        for index in np.ndindex(fixture["mean"].shape)
    ]
    rng = np.random.default_rng((SEED, 1))
    materials = [
        Principled(
            f"white r{r:g} m{m:g} t{t:g}" + "".join(f" {k} {v:g}" for k, v in extra.items()),
            (1, 1, 1),
            m,
            r,
            float(fixture["eta"]),
            spec_trans=t,
            **extra,
        )
        for _, (r, m, t, _, extra) in grid
    ]
    records = material_records(materials)
    wi = incident_directions(rng, np.array([c for _, (*_, c, _) in grid]))
    samples = sample_bsdf(gpu_context, records, wi, rng.random((len(grid), FURNACE_SAMPLES, 3), dtype=np.float32))
    valid = samples[..., 3] > 0.0
    case = np.nonzero(valid)[0]
    values = evaluate_bsdf(gpu_context, records, wi, samples[valid][:, :3], case)
    weights = np.zeros(valid.shape)
    weights[valid] = values[:, 0] / values[:, PDF]
    ours, ours_error = weights.mean(axis=1), weights.std(axis=1, ddof=1) / np.sqrt(FURNACE_SAMPLES)
    theirs = np.array([fixture["mean"][index] for index, _ in grid])
    theirs_error = np.array([fixture["standard_error"][index] for index, _ in grid])
    limit = z_limit(sidak(SIGNIFICANCE, len(grid)))
    # a weight is eval / pdf: both within MITSUBA_RTOL of Mitsuba's where the weights hardly vary (metallic 1)
    difference = np.maximum(np.abs(ours - theirs) - 2 * MITSUBA_RTOL * theirs, 0.0) / np.hypot(ours_error, theirs_error)
    worst = int(np.argmax(difference))
    assert difference.max() <= limit, (
        f"{materials[worst].name} at cos {grid[worst][1][3]}: ours keeps {ours[worst]:.4f} +- {ours_error[worst]:.1g}, "
        f"Mitsuba {theirs[worst]:.4f} +- {theirs_error[worst]:.1g}"
    )
    held = theirs <= 1.0
    excess = np.maximum(ours - 1.0 - 2 * MITSUBA_RTOL, 0.0) / ours_error
    names = np.array([material.name for material in materials])
    assert (excess[held] <= limit).all(), (
        f"{names[held][excess[held] > limit]} keep more than 1 where Mitsuba keeps less"
    )


def test_no_nan_at_the_extremes_and_grazing(gpu_context):
    rng = np.random.default_rng(SEED)
    materials = [
        Principled(f"x{i}", (c, c, c), m, r, spec_trans=t)
        for i, (c, m, r, t) in enumerate(
            (c, m, r, t) for c in (0.0, 1.0) for m in (0.0, 1.0) for r in (0.0, 1.0) for t in (0.0, 1.0)
        )
    ]
    cosines = np.array([1.0, 1e-3, 1e-6, 1e-7, -1e-6, -0.5], np.float32)
    wi = incident_directions(rng, np.tile(cosines, len(materials)))
    case = np.arange(len(wi))
    records = material_records(materials)[np.repeat(np.arange(len(materials)), len(cosines))]
    samples = sample_bsdf(gpu_context, records, wi, rng.random((len(wi), 4096, 3), dtype=np.float32))
    assert np.isfinite(samples).all()
    outgoing = np.array([1.0, 1e-3, 1e-7, 0.0, 0.5, -1e-3, -1.0], np.float32)
    wo = incident_directions(rng, np.tile(outgoing, len(wi)))
    out = evaluate_bsdf(gpu_context, records, wi, wo, np.repeat(case, len(outgoing)))
    assert np.isfinite(out).all() and (out >= 0.0).all()


def test_parameters_are_checked_and_exported():
    with pytest.raises(MaterialError, match="spec_trans must be in"):
        Principled("p", spec_trans=1.5)
    with pytest.raises(MaterialError, match="metallic must be in"):
        Principled("p", metallic=1.5)
    material = Principled("p", (0.1, 0.2, 0.3), metallic=0.5, roughness=0.25, eta=1.4)
    assert material.mitsuba_bsdf() == {
        "type": "principled",
        "base_color": {"type": "rgb", "value": [0.1, 0.2, 0.3]},
        "metallic": 0.5,
        "roughness": 0.25,
        "eta": 1.4,
    }
    # transmission: Mitsuba's lobe is on by the key's presence; not wrapped in `twosided` (its inside)
    assert Principled("p", spec_trans=0.25).mitsuba_bsdf()["spec_trans"] == 0.25
    assert eta_from_specular(0.5) == pytest.approx(1.5, rel=1e-12)
    with pytest.raises(MaterialError, match=r"material 'p': clearcoat_gloss must be in \[0.0, 1.0\], got 2.0"):
        Principled("p", clearcoat_gloss=2.0)
    # the clearcoat, sheen and anisotropy likewise by their weights' keys, their other parameters with them
    values = (0.5, 0.25, 0.75, 0.5, 0.6)
    coated = Principled("p", **dict(zip(LOBE_PARAMETERS, values, strict=True))).mitsuba_bsdf()
    assert {k: coated[k] for k in LOBE_PARAMETERS} == dict(zip(LOBE_PARAMETERS, values, strict=True))
    assert not set(LOBE_PARAMETERS) & set(Principled("p", clearcoat_gloss=0.5, sheen_tint=1.0).mitsuba_bsdf())
    # Mitsuba's anisotropy follows dP/du: a turned one has no export
    with pytest.raises(MaterialError, match="anisotropy_rotation 0.5 has no Mitsuba 3 parameter"):
        Principled("p", anisotropic=0.5, anisotropy_rotation=0.5).mitsuba_bsdf()
    with pytest.raises(MaterialError, match=r"anisotropy_rotation must be in \[-6.28"):
        Principled("p", anisotropy_rotation=7.0)
