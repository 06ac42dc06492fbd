"""The checks a benchmark makes before it times anything: an image on its own (finite, nothing
dropped, sane brightness), two images' mean radiance by a paired z-test, and a BVH's structure."""

from __future__ import annotations

import math

import numpy as np

from wgputrace.bvh import BVH
from wgputrace.testing.stats import sidak, z_limit

CHANNELS = ("red", "green", "blue")


def sidak_critical_z(family_significance: float, tests: int) -> float:
    """Two-sided standard-normal bound so that `tests` tests together err with that probability.

    Sidak's bound holds for two-sided z-tests on jointly normal statistics whatever their
    correlation, and the channels of one image are strongly correlated."""
    return z_limit(sidak(family_significance, tests))


def agreement(image: np.ndarray, baseline: np.ndarray, z_critical: float) -> dict:
    """Paired z-test per channel that two images have the same expected mean radiance.

    D_p = image_p - baseline_p per pixel p (P pixels). Every pixel has its own random stream, so the
    D_p are independent of each other, and if both images estimate the same picture, E[D_p] = 0.
    The image mean of D then has variance Var(D)/P, estimated by the sample variance of the D_p:
    the standard error comes from the per-pixel spread of the differences, which holds only noise,
    not the picture (the picture cancels in D). With P in the thousands, mean(D)/SE is standard
    normal. This holds whatever the correlation between the two images, so the same test serves
    images from the same random numbers (the spread is then small and the test sharp; identical
    images give D = 0 and pass) and from independent ones.
    """
    differences = (image.astype(np.float64) - baseline.astype(np.float64)).reshape(-1, 3)
    mean = differences.mean(axis=0)
    standard_error = differences.std(axis=0, ddof=1) / math.sqrt(len(differences))
    # A zero spread means identical images: then the mean difference is zero as well.
    z = np.divide(mean, standard_error, out=np.zeros(3), where=standard_error > 0)
    failures = [
        f"{channel}: mean radiance differs by {m:.3g} = {score:.2f} standard errors (limit {z_critical:.2f})"
        for channel, m, score in zip(CHANNELS, mean, z, strict=True)
        if abs(score) > z_critical
    ]
    return {
        "mean_difference": mean.tolist(),
        "standard_error": standard_error.tolist(),
        "z": z.tolist(),
        "identical_pixel_fraction": float(np.mean(np.all(differences == 0.0, axis=1))),
        "failures": failures,
    }


def image_failures(image: np.ndarray, dropped: int, band: tuple[float, float] | None = None) -> list[str]:
    """What is wrong with one image on its own: non-finite values, samples the shader dropped, and
    (where `band` is given) a mean radiance outside it, a coarse gate against missing lights or
    exploding path weights, not an accuracy test."""
    failures = []
    finite = np.isfinite(image)
    if not finite.all():
        failures.append(f"{np.count_nonzero(~finite)} image values are NaN or infinite")
    if dropped:
        failures.append(f"the shader dropped {dropped} samples (non-finite or cut short)")
    if band is not None and finite.all():
        mean = float(np.mean(image, dtype=np.float64))
        if not band[0] <= mean <= band[1]:
            failures.append(f"mean radiance {mean:.4g} is outside the sane band [{band[0]}, {band[1]}]")
    return failures


def bvh_failures(bvh: BVH, vertices: np.ndarray) -> list[str]:
    """What makes a tree over `vertices` ((N, 3, 3) corners) invalid: its triangle order not a
    permutation, a triangle in no leaf or in two, a root box other than the mesh's bounds."""
    failures = []
    count = len(vertices)
    if not np.array_equal(np.sort(bvh.triangle_order), np.arange(count)):
        failures.append("triangle_order is not a permutation of the triangles")
    leaves = bvh.triangle_count > 0
    first, size = bvh.left_or_first[leaves].astype(np.int64), bvh.triangle_count[leaves].astype(np.int64)
    # every slot of every leaf's range [first, first + size), as one flat array
    slots = np.repeat(first - (np.cumsum(size) - size), size) + np.arange(size.sum())
    covered = np.bincount(slots, minlength=count)
    if not np.all(covered == 1):
        failures.append(f"{np.count_nonzero(covered != 1)} triangle slots are not in exactly one leaf")
    corners = vertices.reshape(-1, 3)
    if not (
        np.array_equal(bvh.bounds_min[0], corners.min(axis=0))
        and np.array_equal(bvh.bounds_max[0], corners.max(axis=0))
    ):
        failures.append(f"root box {bvh.bounds_min[0]} .. {bvh.bounds_max[0]} is not the mesh's bounds")
    return failures
