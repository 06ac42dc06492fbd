"""Writes tests/shaders/data/principled_furnace_mitsuba.npz: Mitsuba 3's own white furnace for its
`principled` BSDF, what a white (base colour 1) surface keeps of light arriving from outside, on a
grid of roughness x metallic x spec_trans x incident angle x optional lobes (none, a clearcoat, a
tinted sheen): the mean of `sample`'s weights (eval /
pdf, cosine included, in radiance transport) over SAMPLES draws, with its standard error.
`test_white_furnace_is_mitsubas` holds ours to these values, and to at most 1 wherever these are.

Light from outside only: from inside, transmission's radiance weight carries eta^2 (the solid angle
compressed on the way out), which is above 1 by design.

Run with a Python that has Mitsuba 3 (tested with 3.9.1):
    python scripts/make_principled_furnace.py            # a JIT variant: llvm_ad_rgb
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from wgputrace.reference.mitsuba_scene import LLVM_VARIANT, load_mitsuba

FURNACE = Path(__file__).resolve().parent.parent / "tests" / "shaders" / "data" / "principled_furnace_mitsuba.npz"
SEED = 20261202
SAMPLES = 2**21
ETA = 1.5
ROUGHNESS = (0.05, 0.5, 1.0)
METALLIC = (0.0, 0.5, 1.0)
SPEC_TRANS = (0.0, 0.5, 1.0)
# down to grazing
INCIDENT_COSINES = (0.9, 0.5, 0.1, 0.01)
# Principled's optional lobes: none, a glossy clearcoat, a half-tinted sheen (parameter, value) pairs
LOBES = ((), (("clearcoat", 1.0), ("clearcoat_gloss", 0.7)), (("sheen", 1.0), ("sheen_tint", 0.5)))
AXES = (ROUGHNESS, METALLIC, SPEC_TRANS, INCIDENT_COSINES, tuple(range(len(LOBES))))


def grid_point(index: tuple[int, ...]) -> tuple[float, ...]:
    """(roughness, metallic, spec_trans, cos theta, index into LOBES) at a grid index."""
    return tuple(axis[i] for axis, i in zip(AXES, index, strict=True))


def furnace(
    mi, roughness: float, metallic: float, spec_trans: float, cos_theta: float, lobes: int, rng
) -> tuple[float, float]:
    """Mean and standard error of the sample weights of a white principled BSDF with LOBES[lobes]
    for wi at `cos_theta` (azimuth 0: the BSDF is isotropic)."""
    import drjit as dr

    bsdf = mi.load_dict(
        {
            "type": "principled",
            "base_color": {"type": "rgb", "value": [1.0, 1.0, 1.0]},
            "metallic": metallic,
            "roughness": roughness,
            "spec_trans": spec_trans,
            "eta": ETA,
            **dict(LOBES[lobes]),
        }
    )
    # one vectorised call: a JIT variant (llvm_ad_rgb) draws them all at once
    si = dr.zeros(mi.SurfaceInteraction3f, SAMPLES)
    si.wi = mi.Vector3f(float(np.sqrt(1.0 - cos_theta**2)), 0.0, float(cos_theta))
    si.sh_frame = mi.Frame3f(mi.Vector3f(0.0, 0.0, 1.0))
    u = rng.random((3, SAMPLES), dtype=np.float32)
    _, weight = bsdf.sample(mi.BSDFContext(), si, mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    weights = np.array(weight.x, np.float64)
    if not np.isfinite(weights).all():
        raise RuntimeError(f"Mitsuba's principled gives non-finite weights at r{roughness} m{metallic} t{spec_trans}")
    return float(weights.mean()), float(weights.std(ddof=1) / np.sqrt(SAMPLES))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--variant", default=LLVM_VARIANT, help=f"a vectorised Mitsuba variant (default {LLVM_VARIANT})"
    )
    args = parser.parse_args(argv)
    mi = load_mitsuba(args.variant)
    rng = np.random.default_rng(SEED)
    shape = tuple(len(axis) for axis in AXES)
    mean, error = np.zeros(shape), np.zeros(shape)
    for index in np.ndindex(shape):
        mean[index], error[index] = furnace(mi, *grid_point(index), rng)
    FURNACE.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(
        FURNACE,
        roughness=np.array(ROUGHNESS),
        metallic=np.array(METALLIC),
        spec_trans=np.array(SPEC_TRANS),
        cos_theta=np.array(INCIDENT_COSINES),
        lobes=np.array([[value for _, value in lobes] for lobes in LOBES[1:]]),
        lobe_names=np.array([[name for name, _ in lobes] for lobes in LOBES[1:]]),
        eta=ETA,
        samples=SAMPLES,
        mean=mean,
        standard_error=error,
        mitsuba_version=mi.__version__,
        variant=mi.variant(),
    )
    largest = np.unravel_index(np.argmax(mean), shape)
    print(
        f"wrote {FURNACE}; largest {mean[largest]:.4f} +- {error[largest]:.1g} at roughness, metallic, spec_trans, cos, lobes "
        f"{grid_point(largest)}"
    )


if __name__ == "__main__":
    main()
