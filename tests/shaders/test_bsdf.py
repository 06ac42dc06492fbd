"""Sampling consistency of the shipped BSDFs (WGSL `bsdf_sample`, `bsdf_eval`, `bsdf_pdf` over every
material), with the random numbers fed from numpy so every run sees the same samples. The
chi-square suite is separate."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Glass, Glossy
from wgputrace.gpu.layout import MATERIAL, GpuStruct
from wgputrace.render.scene_records import material_records
from wgputrace.testing.bsdf_grid import UNIT_LENGTH_TOLERANCE, incident_directions, refraction_indices, sin_theta
from wgputrace.testing.harness import run_kernel
from wgputrace.testing.oracles import UNIT_ROUNDOFF, as_vec4, fresnel_dielectric, relative_error

pytestmark = pytest.mark.gpu

SAMPLE_RECORD = GpuStruct(
    "SampleRecord",
    (
        ("direction", "vec3<f32>"),
        ("pdf", "f32"),
        ("weight", "vec3<f32>"),
        ("is_delta", "u32"),
        ("eval", "vec3<f32>"),
        ("eval_pdf", "f32"),
    ),
    "bsdf_sample's result, and bsdf_eval / bsdf_pdf at the direction it chose.",
)

KERNEL = f"""
//! include "materials/bsdf.wgsl"
{SAMPLE_RECORD.wgsl()}
fn compute(i: u32) -> SampleRecord {{
    let material = inputs_0[i];
    let wi = inputs_1[i].xyz;
    let u = inputs_2[i];
    let sample = bsdf_sample(material, wi, u.xy, u.z);
    let eval = bsdf_eval(material, wi, sample.direction);
    return SampleRecord(sample.direction, sample.pdf, sample.weight, u32(sample.is_delta), eval, bsdf_pdf(material, wi, sample.direction));
}}
"""
# Every run is padded to this many samples, so the whole file compiles the kernel once.
BATCH = 1 << 16

# Incident cosines, down to grazing; each is used from both sides of the surface.
COS_THETAS = (1.0, 0.7, 0.3, 0.1, 1e-2)
SAMPLES_PER_ANGLE = 2_000
# weight = eval / pdf holds up to float32 rounding of D, G1 and the half vector in each (tens of
# roundings); a relative 1e-4 is ~1700 roundings, so only a real mismatch of formulas fails.
WEIGHT_TOLERANCE = 1e-4
# Except where glossy's half vector m = normalize(wi + wo) is ill-conditioned: |wi + wo| = 2 wi.m,
# so m carries ~u / (wi.m) of cancellation error (wi.m ~ 0.01 at grazing incidence), which D and
# G1 amplify by up to ~1 / alpha; eval and pdf recompute m, and the compiler may round each
# differently (lavapipe: two calls of glossy_pdf on the same inputs differ by up to 7e-4 there).
# Allow this many roundings of that size; a wrong formula is off by O(1), not by 1e-3.
HALF_VECTOR_ROUNDINGS = 32
GLOSSY_ROUGHNESS = (0.05, 0.3, 1.0)  # GGX alpha = roughness (never clamped at these values)

# Diffuse mean cosine: cos theta_o of a cosine-weighted sample has mean 2/3 and variance
# E[cos^2] - 4/9 = 1/2 - 4/9 = 1/18.
MEAN_COSINE_SEED = 72024
MEAN_COSINE_SAMPLES = 6_000  # per incident angle and side: 10 angles fill one BATCH
MEAN_COSINE = 2.0 / 3.0
COSINE_VARIANCE = 1.0 / 18.0
# |z| above this has probability 6e-5 per angle, 6e-4 over the ten checks: a failure is a bug.
Z_LIMIT = 4.0

GLASS_IORS = (1.33, 1.51714, 2.4)
GLASS_ANGLES = 2_000
# The largest float32 below 1: a lobe choice u < R with this u takes refraction unless R = 1.
U_BELOW_ONE = float(np.nextafter(np.float32(1.0), np.float32(0.0)))
# Snell's law and Fresnel from float32 sqrt(1 - eta^2 sin^2): near the critical angle cos_t is
# tiny and carries the rounding of 1 - eta^2 sin^2 divided by 2 cos_t; 16 roundings over that.
GLASS_ROUNDINGS = 16
# Lobe choice just either side of R: u = R (1 -+ this) must reflect, resp. refract.
LOBE_THRESHOLD_STEP = 1e-3


def run_samples(context, materials: np.ndarray, wi: np.ndarray, u: np.ndarray) -> np.ndarray:
    """SAMPLE_RECORD per (material, wi, u): u[:, :2] drives the lobe's direction, u[:, 2] the lobe choice."""
    count = len(wi)
    assert count <= BATCH, f"{count} samples exceed one batch of {BATCH}"
    # np.concatenate would pack the structured dtype (dropping its padding): fill arrays instead.
    assert materials.dtype == MATERIAL.dtype, "materials must keep the GPU layout MATERIAL.dtype"
    inputs = [MATERIAL.zeros(BATCH), np.zeros((BATCH, 4), np.float32), np.zeros((BATCH, 4), np.float32)]
    for padded, values in zip(inputs, (materials, as_vec4(wi), u), strict=True):
        padded[:count] = values
        padded[count:] = values[0]
    out = run_kernel(
        context,
        KERNEL,
        inputs,
        SAMPLE_RECORD.dtype,
        BATCH,
        input_types=["Material", "vec4<f32>", "vec4<f32>"],
        output_type="SampleRecord",
    )
    return out[:count]


def uniforms(rng: np.random.Generator, count: int, lobe: float | np.ndarray | None = None) -> np.ndarray:
    """(count, 4) float32 random numbers in [0, 1); column 2, the lobe choice, fixed if given."""
    u = rng.random((count, 4), dtype=np.float32)
    if lobe is not None:
        u[:, 2] = lobe
    return u


def incident_angles() -> np.ndarray:
    """Each cosine of COS_THETAS from above and below, SAMPLES_PER_ANGLE times."""
    signed = np.concatenate([np.array(COS_THETAS), -np.array(COS_THETAS)])
    return np.repeat(signed, SAMPLES_PER_ANGLE)


def consistency_tolerance(material: Diffuse | Glossy, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """Relative tolerance of weight vs eval / pdf per sample: WEIGHT_TOLERANCE, or for glossy the
    half-vector conditioning bound where that is larger (see HALF_VECTOR_ROUNDINGS)."""
    if not isinstance(material, Glossy):
        return np.full(len(wi), WEIGHT_TOLERANCE)
    alpha = material.roughness
    half = wi.astype(np.float64) + wo
    cos_half = np.abs(np.sum(wi * half, axis=1)) / np.linalg.norm(half, axis=1)
    return np.maximum(WEIGHT_TOLERANCE, HALF_VECTOR_ROUNDINGS * UNIT_ROUNDOFF * (1.0 + 1.0 / alpha) / cos_half)


@pytest.mark.parametrize(
    "material",
    [Diffuse("diffuse", color=(0.8, 0.5, 0.2))]
    + [Glossy(f"glossy {r}", color=(0.9, 0.7, 0.4), roughness=r) for r in GLOSSY_ROUGHNESS],
    ids=lambda m: m.name,
)
def test_sample_weight_is_eval_over_pdf(gpu_context, rng, material):
    cos_i = incident_angles()
    wi = incident_directions(rng, cos_i)
    records = np.repeat(material_records([material]), len(wi))
    out = run_samples(gpu_context, records, wi, uniforms(rng, len(wi)))
    valid = out["pdf"] > 0.0
    # Glossy may draw a microfacet that reflects below the horizon: such samples carry nothing.
    assert np.all(out["weight"][~valid] == 0.0), "a sample with pdf 0 has a nonzero weight"
    for cos in COS_THETAS:
        for side in (1.0, -1.0):
            angle = cos_i == side * cos
            assert valid[angle].mean() > 0.25, f"wi.z = {side * cos}: only {valid[angle].mean():.0%} of samples valid"
    s = out[valid]
    assert np.all(s["is_delta"] == material.delta), (
        f"{material.name}: samples disagree with {type(material).__name__}.delta"
    )
    length = np.linalg.norm(s["direction"].astype(np.float64), axis=1)
    assert np.max(np.abs(length - 1.0)) <= UNIT_LENGTH_TOLERANCE, (
        f"direction length off by {np.max(np.abs(length - 1.0)):.3g}"
    )
    # Two-sided: the sample leaves on the side wi came from.
    same_side = np.sign(s["direction"][:, 2]) == np.sign(cos_i[valid])
    assert same_side.all(), f"{(~same_side).sum()} samples cross to the other side of a two-sided surface"
    wi_valid = wi[valid]
    tolerance = consistency_tolerance(material, wi_valid, s["direction"].astype(np.float64))
    pdf_error = relative_error(s["eval_pdf"], s["pdf"]) / tolerance
    worst = np.argmax(pdf_error)
    assert pdf_error[worst] <= 1.0, (
        f"sample pdf {s['pdf'][worst]} vs bsdf_pdf {s['eval_pdf'][worst]} at wi {wi_valid[worst]}, "
        f"wo {s['direction'][worst]} (tolerance {tolerance[worst]:.3g})"
    )
    expected = s["eval"].astype(np.float64) / s["eval_pdf"][:, None]
    weight_error = relative_error(s["weight"].astype(np.float64), expected).max(axis=1) / tolerance
    worst = np.argmax(weight_error)
    assert weight_error[worst] <= 1.0, (
        f"weight {s['weight'][worst]} vs eval / pdf {expected[worst]} at wi {wi_valid[worst]}, "
        f"wo {s['direction'][worst]} (tolerance {tolerance[worst]:.3g})"
    )


def test_diffuse_mean_cosine_is_two_thirds(gpu_context):
    rng = np.random.default_rng(MEAN_COSINE_SEED)
    signed = np.concatenate([np.array(COS_THETAS), -np.array(COS_THETAS)])
    cos_i = np.repeat(signed, MEAN_COSINE_SAMPLES)
    records = np.repeat(material_records([Diffuse("diffuse")]), len(cos_i))
    out = run_samples(gpu_context, records, incident_directions(rng, cos_i), uniforms(rng, len(cos_i)))
    cos_o = np.abs(out["direction"][:, 2].astype(np.float64)).reshape(len(signed), MEAN_COSINE_SAMPLES)
    z = (cos_o.mean(axis=1) - MEAN_COSINE) / np.sqrt(COSINE_VARIANCE / MEAN_COSINE_SAMPLES)
    worst = np.argmax(np.abs(z))
    assert np.abs(z[worst]) <= Z_LIMIT, (
        f"mean cos theta_o {cos_o[worst].mean():.5f} at wi.z {signed[worst]}: z = {z[worst]:.2f} beyond {Z_LIMIT}"
    )


def glass_cases(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(material records, ior, wi): every ior, from outside and inside, cosines uniform in (0, 1] plus grazing."""
    ior = np.repeat(np.array(GLASS_IORS), 2 * GLASS_ANGLES)
    cos = np.concatenate([rng.uniform(0.0, 1.0, GLASS_ANGLES - 3), [1.0, 1e-2, 1e-3]])
    side = np.tile(np.repeat([1.0, -1.0], GLASS_ANGLES), len(GLASS_IORS))
    cos_i = np.maximum(np.tile(cos, 2 * len(GLASS_IORS)), 1e-4) * side
    records = material_records([Glass(f"glass {n}", color=(0.9, 0.8, 0.7), ior=n) for n in GLASS_IORS])
    return np.repeat(records, 2 * GLASS_ANGLES), ior, incident_directions(rng, cos_i)


def fresnel_tolerance(ior: np.ndarray, wi: np.ndarray) -> np.ndarray:
    """Absolute error allowed for a float32 reflectance: GLASS_ROUNDINGS over 2 cos_t (see above)."""
    eta_i, eta_t = refraction_indices(ior, wi)
    cos_t2 = 1.0 - (eta_i / eta_t) ** 2 * sin_theta(wi) ** 2
    return GLASS_ROUNDINGS * UNIT_ROUNDOFF / np.sqrt(np.maximum(cos_t2, UNIT_ROUNDOFF))


def test_glass_reflection_and_refraction_directions(gpu_context, rng):
    records, ior, wi = glass_cases(rng)
    eta_i, eta_t = refraction_indices(ior, wi)
    # wi.z is what the shader takes for cos theta_i, so the reference does too
    reflectance = fresnel_dielectric(wi[:, 2], eta_i, eta_t)
    reflected = run_samples(gpu_context, records, wi, uniforms(rng, len(wi), lobe=0.0))
    refracted = run_samples(gpu_context, records, wi, uniforms(rng, len(wi), lobe=U_BELOW_ONE))
    assert Glass.delta and np.all(reflected["is_delta"] == 1) and np.all(refracted["is_delta"] == 1), (
        "glass lobes are deltas"
    )

    mirror = wi * np.array([-1.0, -1.0, 1.0], np.float32)
    assert np.array_equal(reflected["direction"], mirror), "reflection is not the mirror direction (-x, -y, z)"

    transmits = reflectance < 1.0
    t = refracted[transmits]
    t_wi, t_eta_i, t_eta_t = wi[transmits], eta_i[transmits], eta_t[transmits]
    length = np.linalg.norm(t["direction"].astype(np.float64), axis=1)
    tolerance = fresnel_tolerance(ior[transmits], t_wi)
    assert np.all(np.abs(length - 1.0) <= tolerance + UNIT_LENGTH_TOLERANCE), "refracted direction not unit length"
    crossed = np.sign(t["direction"][:, 2]) == -np.sign(t_wi[:, 2])
    assert crossed.all(), f"{(~crossed).sum()} refracted directions stay on the incident side"
    # Snell: eta_i sin_i = eta_t sin_t, in the plane of incidence, on the far side of the normal.
    snell = relative_error(t_eta_t * sin_theta(t["direction"]), t_eta_i * sin_theta(t_wi))
    worst = np.argmax(snell)
    assert snell[worst] <= 4 * UNIT_LENGTH_TOLERANCE, f"Snell's law off by {snell[worst]:.3g} for wi {t_wi[worst]}"
    along = np.sum(t["direction"][:, :2].astype(np.float64) * t_wi[:, :2], axis=1)
    wo = t["direction"].astype(np.float64)
    across = wo[:, 0] * t_wi[:, 1] - wo[:, 1] * t_wi[:, 0]
    assert np.all(along <= 0.0), "the refracted direction is not across the normal from wi"
    assert np.all(np.abs(across) <= UNIT_LENGTH_TOLERANCE * sin_theta(t_wi)), "refraction leaves the plane of incidence"


def test_glass_reflection_probability_is_fresnel(gpu_context, rng):
    records, ior, wi = glass_cases(rng)
    eta_i, eta_t = refraction_indices(ior, wi)
    reflectance = fresnel_dielectric(wi[:, 2], eta_i, eta_t)
    tolerance = fresnel_tolerance(ior, wi)
    reflected = run_samples(gpu_context, records, wi, uniforms(rng, len(wi), lobe=0.0))
    error = np.abs(reflected["pdf"] - reflectance)
    worst = np.argmax(error / tolerance)
    assert error[worst] <= tolerance[worst], (
        f"reflection probability {reflected['pdf'][worst]} vs Fresnel {reflectance[worst]:.7f} "
        f"for wi {wi[worst]}, ior {ior[worst]}"
    )
    # The lobe is chosen by u < R: u a little below R reflects, a little above refracts (with
    # probability 1 - R), so a uniform u reflects with probability R.
    decidable = (reflectance > 10 * tolerance) & (reflectance * (1.0 + LOBE_THRESHOLD_STEP) + tolerance < 1.0)
    below = run_samples(
        gpu_context, records, wi, uniforms(rng, len(wi), lobe=reflectance * (1.0 - LOBE_THRESHOLD_STEP) - tolerance)
    )
    above = run_samples(
        gpu_context, records, wi, uniforms(rng, len(wi), lobe=reflectance * (1.0 + LOBE_THRESHOLD_STEP) + tolerance)
    )
    reflects_below = np.sign(below["direction"][:, 2]) == np.sign(wi[:, 2])
    refracts_above = np.sign(above["direction"][:, 2]) == -np.sign(wi[:, 2])
    assert reflects_below[decidable].all(), f"{(~reflects_below[decidable]).sum()} samples with u < R refract"
    assert refracts_above[decidable].all(), f"{(~refracts_above[decidable]).sum()} samples with u > R reflect"
    refraction_pdf = above["pdf"][decidable]
    assert np.all(np.abs(refraction_pdf - (1.0 - reflectance[decidable])) <= tolerance[decidable]), (
        "refraction is not chosen with probability 1 - R"
    )


def test_glass_total_internal_reflection(gpu_context, rng):
    records, ior, wi = glass_cases(rng)
    inside = wi[:, 2] < 0.0
    beyond_critical = inside & (sin_theta(wi) * ior > 1.0 + 1e-4)
    assert beyond_critical.sum() > 1000, "too few directions beyond the critical angle"
    records, ior, wi = records[beyond_critical], ior[beyond_critical], wi[beyond_critical]
    out = run_samples(gpu_context, records, wi, uniforms(rng, len(wi)))  # any lobe choice u in [0, 1)
    stays = np.array_equal(out["direction"], wi * np.array([-1.0, -1.0, 1.0], np.float32))
    assert stays, "a direction beyond the critical angle leaves the glass"
    assert np.all(out["pdf"] == 1.0), "total internal reflection is not chosen with probability 1"
