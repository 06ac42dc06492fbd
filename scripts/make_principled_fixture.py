"""Writes tests/shaders/data/principled_mitsuba.npz: Mitsuba 3's `principled` BSDF evaluated (eval,
which includes cos theta_o, and pdf) at random directions for a few parameter sets, the independent
implementation `test_eval_and_pdf_match_mitsuba` compares WGSL `principled_eval` and `principled_pdf` with,
each BSDF made by `Principled.mitsuba_bsdf` (so the export is tested too).
Without transmission both directions lie above the surface (ours is two-sided there, Mitsuba's
black below); with it, anywhere on the sphere (inside, reflection and refraction included).

Run with a Python that has Mitsuba 3 (tested with 3.9.1, variant llvm_ad_rgb):
    python scripts/make_principled_fixture.py
"""

from __future__ import annotations

from pathlib import Path

import drjit as dr
import mitsuba as mi
import numpy as np

from wgputrace import Principled

FIXTURE = Path(__file__).resolve().parent.parent / "tests" / "shaders" / "data" / "principled_mitsuba.npz"
SEED = 20261201
DIRECTIONS = 64
# base_color, metallic, roughness, eta, spec_trans (and clearcoat, clearcoat_gloss, sheen,
# sheen_tint: LOBES): the corners of the range, eta below 1 (Schlick on the refracted side),
# transmission partial and whole, then the clearcoat and sheen lobes, alone, tinted and together
# (clearcoat_gloss at most 0.5: near a glossier GTR1 peak Mitsuba's D, 1 + (alpha^2 - 1) cos^2 in f32,
# cancels to fewer bits than MITSUBA_RTOL; ours is written without the cancellation), then anisotropy
# (alpha_u along x: the sh_frame's s) on dielectric, metal, transmission, at alpha's floor, with the lobes
LOBES = ("clearcoat", "clearcoat_gloss", "sheen", "sheen_tint", "anisotropic")
PARAMETERS = (
    ((0.9, 0.5, 0.2), 0.0, 0.5, 1.5, 0.0),
    ((0.3, 0.6, 0.9), 0.5, 0.2, 1.33, 0.0),
    ((1.0, 1.0, 1.0), 1.0, 0.05, 1.5, 0.0),
    ((0.8, 0.8, 0.8), 0.25, 1.0, 2.4, 0.0),
    ((0.2, 0.9, 0.4), 0.75, 0.7, 0.8, 0.0),
    ((0.0, 0.0, 0.0), 0.0, 0.0, 1.5, 0.0),
    ((0.9, 0.5, 0.2), 0.0, 0.3, 1.5, 0.5),
    ((0.6, 0.8, 1.0), 0.0, 0.1, 1.5, 1.0),
    ((1.0, 1.0, 1.0), 0.3, 0.8, 1.33, 0.7),
    ((0.5, 0.5, 0.5), 0.5, 0.5, 0.8, 1.0),
    ((0.9, 0.5, 0.2), 0.0, 0.5, 1.5, 0.0, 1.0, 0.5, 0.0, 0.0),
    ((0.3, 0.6, 0.9), 0.5, 0.2, 1.33, 0.0, 0.7, 0.0, 0.0, 0.0),
    ((0.2, 0.9, 0.4), 0.0, 0.7, 0.8, 0.0, 0.5, 0.2, 0.0, 0.0),
    ((0.9, 0.5, 0.2), 0.0, 0.5, 1.5, 0.0, 0.0, 0.0, 1.0, 0.0),
    ((0.3, 0.6, 0.9), 0.25, 0.8, 1.5, 0.0, 0.0, 0.0, 0.7, 0.5),
    ((0.0, 0.0, 0.0), 0.0, 0.5, 1.5, 0.0, 0.0, 0.0, 1.0, 1.0),
    ((0.6, 0.8, 1.0), 0.0, 0.3, 1.5, 0.5, 0.8, 0.3, 0.6, 1.0),
    # sheen without a diffuse lobe: Mitsuba's JIT variants add it all the same
    ((0.6, 0.8, 1.0), 0.0, 0.3, 1.5, 1.0, 0.0, 0.0, 1.0, 0.0),
    ((0.9, 0.5, 0.2), 0.0, 0.5, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.8),
    ((1.0, 1.0, 1.0), 1.0, 0.3, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
    ((0.3, 0.6, 0.9), 0.5, 0.1, 1.33, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5),
    ((0.6, 0.8, 1.0), 0.0, 0.4, 1.5, 0.7, 0.0, 0.0, 0.0, 0.0, 0.9),
    ((0.5, 0.5, 0.5), 0.0, 0.6, 0.8, 1.0, 0.0, 0.0, 0.0, 0.0, 0.3),
    ((0.5, 0.5, 0.5), 0.25, 0.03, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
    ((0.2, 0.9, 0.4), 0.3, 0.7, 1.5, 0.0, 0.6, 0.3, 0.5, 0.5, 0.7),
)


def upper_hemisphere(rng: np.random.Generator, count: int) -> np.ndarray:
    """Directions with cos theta in [0.01, 1] at random azimuths (grazing ones included)."""
    z = rng.uniform(0.01, 1.0, count)
    phi = rng.uniform(0.0, 2.0 * np.pi, count)
    s = np.sqrt(1.0 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1).astype(np.float32)


def sphere(rng: np.random.Generator, count: int) -> np.ndarray:
    """Directions with |cos theta| in [0.01, 1], each below the surface with probability 1/2."""
    directions = upper_hemisphere(rng, count)
    directions[rng.random(count) < 0.5, 2] *= -1.0
    return directions


def main() -> None:
    mi.set_variant("llvm_ad_rgb")
    rng = np.random.default_rng(SEED)
    context = mi.BSDFContext()
    wis, wos, evals, pdfs = [], [], [], []
    for base_color, metallic, roughness, eta, spec_trans, *lobes in PARAMETERS:
        draw = sphere if spec_trans > 0 else upper_hemisphere
        wi, wo = draw(rng, DIRECTIONS), draw(rng, DIRECTIONS)
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wi = mi.Vector3f(wi.T)
        si.sh_frame = mi.Frame3f(mi.Vector3f(0.0, 0.0, 1.0))
        material = Principled(
            "fixture", base_color, metallic, roughness, eta, spec_trans, **dict(zip(LOBES, lobes, strict=False))
        )
        bsdf = mi.load_dict(material.mitsuba_bsdf())
        wis.append(wi)
        wos.append(wo)
        evals.append(np.array(bsdf.eval(context, si, mi.Vector3f(wo.T))).T)
        pdfs.append(np.array(bsdf.pdf(context, si, mi.Vector3f(wo.T))))
    FIXTURE.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(
        FIXTURE,
        base_color=np.array([p[0] for p in PARAMETERS], np.float32),
        metallic=np.array([p[1] for p in PARAMETERS], np.float32),
        roughness=np.array([p[2] for p in PARAMETERS], np.float32),
        eta=np.array([p[3] for p in PARAMETERS], np.float32),
        spec_trans=np.array([p[4] for p in PARAMETERS], np.float32),
        **{
            name: np.array([(*p[5:], *(0.0,) * len(LOBES))[i] for p in PARAMETERS], np.float32)
            for i, name in enumerate(LOBES)
        },
        wi=np.array(wis),
        wo=np.array(wos),
        eval=np.array(evals, np.float32),
        pdf=np.array(pdfs, np.float32),
        mitsuba_version=mi.__version__,
    )
    print(f"wrote {FIXTURE}")


if __name__ == "__main__":
    main()
