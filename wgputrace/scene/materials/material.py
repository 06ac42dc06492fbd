"""The base of every material: a name, a kind that selects the WGSL code, parameter checks.

Parameters are plain attributes. Assigning one re-runs the material's checks (a bad value raises
MaterialError and leaves the material as it was) and bumps `version`, which is how a Renderer
knows which material record to upload again.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
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
    """A material parameter is out of its documented range; `parameter` names it."""

    def __init__(self, message: str, parameter: str | None = None) -> None:
        super().__init__(message)
        self.parameter = parameter


def check_color(material_name: str, parameter: str, value, *, upper: float | None) -> tuple[float, float, float]:
    """An RGB triple of finite, non-negative numbers (at most `upper` where energy must be conserved)."""
    try:
        rgb = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise MaterialError(
            f"material {material_name!r}: {parameter} must be 3 numbers, got {value!r}", parameter
        ) from None
    if rgb.size == 1:
        rgb = np.repeat(rgb, 3)
    if rgb.size != 3:
        raise MaterialError(f"material {material_name!r}: {parameter} must be 3 numbers, got {value!r}", parameter)
    if not np.all(np.isfinite(rgb)) or np.any(rgb < 0):
        raise MaterialError(
            f"material {material_name!r}: {parameter} must be finite and >= 0, got {value!r}", parameter
        )
    if upper is not None and np.any(rgb > upper):
        raise MaterialError(
            f"material {material_name!r}: {parameter} must be <= {upper} (a reflectance above 1 creates energy), got {value!r}",
            parameter,
        )
    return (float(rgb[0]), float(rgb[1]), float(rgb[2]))


def check_number(
    material_name: str, parameter: str, value, *, low: float, high: float, low_inclusive: bool = True
) -> float:
    """A finite number in [low, high] (or (low, high] when low_inclusive is false)."""
    bracket = "[" if low_inclusive else "("
    message = f"material {material_name!r}: {parameter} must be in {bracket}{low}, {high}], got {value!r}"
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise MaterialError(message, parameter) from None
    below = number < low if low_inclusive else number <= low
    if not math.isfinite(number) or below or number > high:
        raise MaterialError(message, parameter)
    return number


@dataclass(eq=False)
class Material:
    """Materials compare by identity: two triangles share a material only if they share the object."""

    name: str

    kind: ClassVar[MaterialKind]

    def __post_init__(self) -> None:
        for parameter, value in self.checked_parameters().items():
            object.__setattr__(self, parameter, value)
        object.__setattr__(self, "version", 0)

    def __setattr__(self, key: str, value) -> None:
        # During __init__ (no version yet) and for the name, a plain assignment: names never
        # reach the GPU.
        if "version" not in self.__dict__ or key not in self.parameter_names():
            object.__setattr__(self, key, value)
            return
        previous = self.__dict__[key]
        object.__setattr__(self, key, value)
        try:
            checked = self.checked_parameters()
        except MaterialError:
            object.__setattr__(self, key, previous)
            raise
        for parameter, normalized in checked.items():
            object.__setattr__(self, parameter, normalized)
        object.__setattr__(self, "version", self.version + 1)

    @classmethod
    def parameter_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls) if f.name != "name")

    def checked_parameters(self) -> dict[str, object]:
        """Every parameter validated and normalized, or MaterialError naming the first bad one."""
        raise NotImplementedError

    def gpu_parameters(self) -> tuple[tuple[float, float, float], float, float]:
        """(color, alpha, ior) as the shaders read them; see shaders/materials/*.wgsl."""
        raise NotImplementedError
