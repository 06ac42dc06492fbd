"""Vose's alias method: a discrete distribution drawn in O(1). The light sampler's table
(`light_table`) and the environment map's sampling tables (`EnvironmentTables`) are built with
it, here in the scene layer that both reach."""

from __future__ import annotations

import numpy as np


def alias_table(weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vose's alias method: (threshold, alias) such that drawing k uniformly, then keeping k when
    a uniform u < threshold[k] and taking alias[k] otherwise, draws i with weights[i] / sum."""
    weights = np.asarray(weights, dtype=np.float64)
    count = len(weights)
    if count == 0 or not np.all(np.isfinite(weights)) or np.any(weights < 0) or weights.sum() <= 0:
        raise ValueError(f"alias table needs finite non-negative weights with a positive sum, got {weights}")
    scaled = weights * (count / weights.sum())
    threshold = np.ones(count)
    alias = np.arange(count, dtype=np.uint32)
    small = [i for i in range(count) if scaled[i] < 1.0]
    large = [i for i in range(count) if scaled[i] >= 1.0]
    while small and large:
        light, heavy = small.pop(), large.pop()
        threshold[light], alias[light] = scaled[light], heavy
        scaled[heavy] -= 1.0 - scaled[light]
        (small if scaled[heavy] < 1.0 else large).append(heavy)
    # whatever is left is 1 up to rounding: it keeps itself
    return threshold, alias
