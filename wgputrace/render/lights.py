"""The light sampler's table: every light in one alias table, sampled in O(1) by estimated power.

A light triangle is chosen in proportion to area x luminance of its radiance (its power over the
2 pi common to all), then a point uniform on it, so a light point's density per unit area is
luminance(L) / total_weight for every triangle: the shader needs only the radiance it already
reads and `total_weight`. The light sources (each class's `weight`) and the environment (its power
through the scene's bounding sphere) follow the triangles in the same units, as `LIGHT_SOURCE_FLAG`
encodes them, each record carrying its chance of being chosen, which its density needs. A light of
zero power never enters the table. Which materials emit, and what, their classes say.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..gpu.layout import LIGHT
from ..kernels.light_dispatch import ENVIRONMENT_LIGHT, LIGHT_SOURCE_FLAG
from ..scene import material_classes
from ..scene.lights.alias_table import alias_table
from ..scene.lights.light import LUMINANCE_WEIGHTS

__all__ = ["LUMINANCE_WEIGHTS", "LightTable", "alias_table", "emitted_radiance", "emitting", "light_table"]


@dataclass
class LightTable:
    entries: np.ndarray  # LIGHT.dtype: the light triangles, then the light sources, then the environment
    total_weight: float  # the sum of every light's weight (triangles: area x luminance)
    # the chance of choosing each light source (0: zero power, not in the table) and the environment
    source_probability: np.ndarray = field(default_factory=lambda: np.zeros(0))
    environment_probability: float = 0.0

    @property
    def count(self) -> int:
        return len(self.entries)


def emitting_kinds() -> tuple[int, ...]:
    """The material kinds that emit light."""
    return tuple(cls.kind for cls in material_classes() if cls.emission_wgsl is not None)


def emitting(materials: np.ndarray) -> np.ndarray:
    """Which of the MATERIAL records `materials` emit light."""
    return np.isin(materials["kind"], emitting_kinds())


def emitted_radiance(materials: np.ndarray) -> np.ndarray:
    """(n, 3) float64: the radiance each MATERIAL record emits, as the shaders read it from the
    record (its class's `emission`); zero where it emits nothing."""
    radiance = np.zeros((len(materials), 3))
    for cls in material_classes():
        if cls.emission_wgsl is not None:
            rows = materials["kind"] == cls.kind
            radiance[rows] = cls.record_radiance(materials[rows])
    return radiance


def light_table(
    triangles: np.ndarray,
    materials: np.ndarray,
    source_weights: np.ndarray | None = None,
    environment_weight: float = 0.0,
    surface_densities: np.ndarray | None = None,
) -> LightTable:
    """The light table of the emissive triangles of GPU `triangles` records (TRIANGLE.dtype), in the
    triangles' GPU order, with the materials' GPU records (MATERIAL.dtype); of the light sources
    weighing `source_weights` (each light's `weight`, in the scene's order); and of an environment
    weighing `environment_weight`. `surface_densities` (one per triangle) adds the weight per unit
    area of light emitted through the materials' texture records (`footprint_means`), which the
    shaders read back (`light_density`)."""
    surface = np.zeros(len(triangles)) if surface_densities is None else surface_densities
    density = (emitted_radiance(materials) @ LUMINANCE_WEIGHTS)[triangles["material"]] + surface
    index = np.flatnonzero(emitting(materials)[triangles["material"]] | (surface > 0))
    v0, v1, v2 = (triangles[corner][index].astype(np.float64) for corner in ("v0", "v1", "v2"))
    area = 0.5 * np.linalg.norm(np.cross(v1 - v0, v2 - v0), axis=1)
    source_weights = np.zeros(0) if source_weights is None else np.asarray(source_weights, np.float64)
    words = np.concatenate([index, LIGHT_SOURCE_FLAG | np.arange(len(source_weights)), [ENVIRONMENT_LIGHT]]).astype(
        np.uint32
    )
    weight = np.concatenate([area * density[index], source_weights, [environment_weight]])
    keep = weight > 0
    entries = LIGHT.zeros(int(np.count_nonzero(keep)))
    if len(entries) == 0:
        return LightTable(entries, 0.0, np.zeros(len(source_weights)))
    total = float(weight[keep].sum())
    threshold, alias = alias_table(weight[keep])
    entries["triangle"], entries["alias_index"], entries["threshold"] = words[keep], alias, threshold
    sources = slice(len(index), len(index) + len(source_weights))
    return LightTable(entries, total, weight[sources] / total, float(weight[-1] / total))
