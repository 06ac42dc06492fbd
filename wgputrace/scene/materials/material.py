"""The base of every material: a name, a kind that selects the WGSL code, parameter checks."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import ClassVar

import numpy as np


class MaterialKind(IntEnum):
    """Material ids shared with the shaders (trac0r's numbering: 1 emissive ... 4 glossy)."""

    EMITTER = 1
    DIFFUSE = 2
    GLASS = 3
    GLOSSY = 4


class MaterialError(ValueError):
    """A material parameter is out of its documented range."""


def check_color(material_name: str, parameter: str, value, *, upper: float | None) -> tuple[float, float, float]:
    """An RGB triple of finite, non-negative numbers (at most `upper` where energy must be conserved)."""
    rgb = np.asarray(value, dtype=np.float64).reshape(-1)
    if rgb.size == 1:
        rgb = np.repeat(rgb, 3)
    if rgb.size != 3:
        raise MaterialError(f"material {material_name!r}: {parameter} must be 3 numbers, got {value!r}")
    if not np.all(np.isfinite(rgb)) or np.any(rgb < 0):
        raise MaterialError(f"material {material_name!r}: {parameter} must be finite and >= 0, got {value!r}")
    if upper is not None and np.any(rgb > upper):
        raise MaterialError(
            f"material {material_name!r}: {parameter} must be <= {upper} (a reflectance above 1 creates energy), got {value!r}"
        )
    return (float(rgb[0]), float(rgb[1]), float(rgb[2]))


def check_number(
    material_name: str, parameter: str, value, *, low: float, high: float, low_inclusive: bool = True
) -> float:
    """A finite number in [low, high] (or (low, high] when low_inclusive is false)."""
    number = float(value)
    below = number < low if low_inclusive else number <= low
    if not math.isfinite(number) or below or number > high:
        bracket = "[" if low_inclusive else "("
        raise MaterialError(
            f"material {material_name!r}: {parameter} must be in {bracket}{low}, {high}], got {value!r}"
        )
    return number


@dataclass(eq=False)
class Material:
    """Materials compare by identity: two triangles share a material only if they share the object."""

    name: str

    kind: ClassVar[MaterialKind]

    def gpu_parameters(self) -> tuple[tuple[float, float, float], float, float]:
        """(color, alpha, ior) as the shaders read them; see shaders/materials/*.wgsl."""
        raise NotImplementedError
