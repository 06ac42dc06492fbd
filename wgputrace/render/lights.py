"""Emissive triangles as lights: a table sampled in O(1) with an alias table.

Each light triangle is chosen with probability proportional to its emitted power, area x
luminance of its radiance (the factor pi of a Lambertian emitter is common to all and cancels),
then a point uniform on it. The density of a light point per unit area is then
luminance(L) / total_weight for every light, whatever its area: the shader needs no per-triangle
table to evaluate it, only the radiance it already reads and `total_weight`.

Which materials emit, and what, their classes say (scene/materials/material.py: `emission`,
`record_radiance`): a new emitting kind becomes a light with no change here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..gpu.layout import LIGHT
from ..scene import material_classes

# Rec. 709 / sRGB luminance weights; the shaders use the same ones (shaders/light_sampling.wgsl).
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])


@dataclass
class LightTable:
    entries: np.ndarray  # LIGHT.dtype, one per light triangle
    total_weight: float  # sum of area x luminance over all light triangles

    @property
    def count(self) -> int:
        return len(self.entries)


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


def emitting_kinds() -> tuple[int, ...]:
    """The material kinds that emit light."""
    return tuple(cls.kind for cls in material_classes() if cls.emission is not None)


def emitting(materials: np.ndarray) -> np.ndarray:
    """Which of the MATERIAL records `materials` emit light."""
    return np.isin(materials["kind"], emitting_kinds())


def emitted_radiance(materials: np.ndarray) -> np.ndarray:
    """(n, 3) float64: the radiance each MATERIAL record emits, as the shaders read it from the
    record (its class's `emission`); zero where it emits nothing."""
    radiance = np.zeros((len(materials), 3))
    for cls in material_classes():
        if cls.emission is not None:
            rows = materials["kind"] == cls.kind
            radiance[rows] = cls.record_radiance(materials[rows])
    return radiance


def light_table(triangles: np.ndarray, materials: np.ndarray) -> LightTable:
    """Light entries for the emissive triangles of GPU `triangles` records (TRIANGLE.dtype), in the
    triangles' GPU order, with the materials' GPU records (MATERIAL.dtype)."""
    index = np.flatnonzero(emitting(materials)[triangles["material"]])
    radiance = emitted_radiance(materials)[triangles["material"][index]]
    v0, v1, v2 = (triangles[corner][index].astype(np.float64) for corner in ("v0", "v1", "v2"))
    area = 0.5 * np.linalg.norm(np.cross(v1 - v0, v2 - v0), axis=1)
    weight = area * (radiance @ LUMINANCE_WEIGHTS)
    entries = LIGHT.zeros(int(np.count_nonzero(weight > 0)))
    if len(entries) == 0:
        return LightTable(entries, 0.0)
    keep = weight > 0
    threshold, alias = alias_table(weight[keep])
    entries["triangle"], entries["alias_index"], entries["threshold"] = index[keep], alias, threshold
    return LightTable(entries, float(weight[keep].sum()))
