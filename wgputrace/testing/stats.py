"""Statistics for the randomized tests: Sidak-corrected levels, z limits, Pearson's chi-square
goodness-of-fit test with pooling of sparse cells, exact binomial tests, and the power a sample
count buys. Each test states its family's significance level; this module turns it into bounds.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import optimize, stats

from wgputrace import save_image

# Pearson's statistic is close to chi-square distributed only where every cell expects at least
# this many samples (Cochran's rule, as pbrt-v4 and Mitsuba 3 use it); sparser cells are pooled.
MIN_EXPECTED = 5.0


def sidak(significance: float, tests: int) -> float:
    """The level of each of `tests` independent tests that together fail by chance with
    probability `significance`."""
    return 1.0 - (1.0 - significance) ** (1.0 / tests)


def z_limit(level: float) -> float:
    """|z| beyond this has probability `level` under the standard normal (two-sided)."""
    return float(stats.norm.isf(level / 2.0))


@dataclass(frozen=True)
class ChiSquare:
    statistic: float
    dof: int
    p_value: float
    bins: int  # after pooling
    pooled_cells: int  # cells with fewer than MIN_EXPECTED expected, pooled into one bin
    pool_index: np.ndarray = field(repr=False)  # bin of each cell (flattened): apply the same pooling elsewhere


def pool_sparse_cells(expected: np.ndarray) -> np.ndarray:
    """Bin index per cell: cells expecting fewer than MIN_EXPECTED share one bin; if that bin
    still expects fewer, it joins the smallest cell that did not need pooling."""
    expected = np.asarray(expected, np.float64).ravel()
    sparse = expected < MIN_EXPECTED
    index = np.zeros(len(expected), np.int64)
    index[~sparse] = np.arange(1, (~sparse).sum() + 1)
    if expected[sparse].sum() < MIN_EXPECTED and (~sparse).any():
        index[sparse] = index[~sparse][np.argmin(expected[~sparse])]
    # renumber 0..bins-1 in order of first appearance of each bin
    return np.unique(index, return_inverse=True)[1]


def chi_square(observed: np.ndarray, expected: np.ndarray) -> ChiSquare:
    """Pearson's goodness-of-fit test of `observed` counts against `expected` counts (same
    total, any shape). A count in a cell that expects exactly nothing fails the test outright."""
    observed = np.asarray(observed, np.float64).ravel()
    expected = np.asarray(expected, np.float64).ravel()
    if observed.shape != expected.shape:
        raise ValueError(f"observed has {observed.size} cells, expected {expected.size}")
    index = pool_sparse_cells(expected)
    bins = int(index.max()) + 1
    if bins < 2:
        raise ValueError(f"{expected.sum():.3g} expected samples fill fewer than 2 bins of {MIN_EXPECTED} each")
    o = np.bincount(index, observed, minlength=bins)
    e = np.bincount(index, expected, minlength=bins)
    if np.any((expected == 0.0) & (observed > 0.0)):
        statistic = np.inf
    else:
        statistic = float(np.sum((o - e) ** 2 / e))
    p_value = float(stats.chi2.sf(statistic, bins - 1))
    return ChiSquare(statistic, bins - 1, p_value, bins, int((expected < MIN_EXPECTED).sum()), index)


def binomial_p_value(successes: int, trials: int, probability: float) -> float:
    """Exact two-sided p-value of `successes` in `trials` draws with success `probability`."""
    return float(stats.binomtest(int(successes), int(trials), float(probability)).pvalue)


def detectable_misallocation(samples: int, dof: int, level: float, power: float) -> float:
    """The smallest relative error eps of a sampler that a chi-square test of `samples` draws
    with `dof` degrees of freedom at `level` detects with probability `power`.

    eps is measured as probability moved between two halves of the distribution, p' = p (1 + eps)
    on one half and p (1 - eps) on the other: the test statistic then follows a noncentral
    chi-square with noncentrality samples * sum((p' - p)^2 / p) = samples * eps^2.
    """
    critical = stats.chi2.isf(level, dof)

    def missed(noncentrality: float) -> float:
        return stats.ncx2.sf(critical, dof, noncentrality) - power

    upper = 1.0
    while missed(upper) < 0.0:
        upper *= 2.0
    noncentrality = optimize.brentq(missed, 0.0, upper)
    return float(np.sqrt(noncentrality / samples))


# Histogram images: each cell drawn as a square this many pixels wide; residuals at this many
# standard deviations reach full colour.
_CELL_PIXELS = 8
_RESIDUAL_FULL_SCALE = 4.0


def save_histograms(path: Path, observed: np.ndarray, expected: np.ndarray) -> Path:
    """A PNG for a person to compare 2-D histograms: observed and expected counts (grey, on one
    scale) and the residual (observed - expected) / sqrt(expected) (red above, blue below)."""
    observed = np.asarray(observed, np.float64)
    expected = np.asarray(expected, np.float64)
    scale = max(observed.max(), expected.max(), 1.0)
    residual = (observed - expected) / np.sqrt(np.maximum(expected, 1.0)) / _RESIDUAL_FULL_SCALE
    grey = [np.repeat((a / scale)[..., None], 3, axis=-1) for a in (observed, expected)]
    signed = np.stack([np.clip(residual, 0, 1), np.zeros_like(residual), np.clip(-residual, 0, 1)], axis=-1)
    gap = np.ones((observed.shape[0], 1, 3))
    panels = np.concatenate([grey[0], gap, grey[1], gap, signed], axis=1)
    return save_image(path, np.repeat(np.repeat(panels, _CELL_PIXELS, axis=0), _CELL_PIXELS, axis=1))
