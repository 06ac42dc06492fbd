"""What material and light kinds share: the registry of a family's classes by kind id, the base class
whose subclasses register themselves and re-check their parameters when one is assigned, the checks
those parameters share, and the import of a family's package that makes every kind in it register.

A class registers itself as a kind when its body sets `kind`; subclassing a kind without setting one
makes a variant of that kind. Parameters (the dataclass fields but `name`) are plain attributes:
assigning one re-runs `checked_parameters` (the family's error leaves the object as it was) and
bumps `version`, which is how a Renderer knows which record to upload again.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable
from dataclasses import fields
from importlib import import_module
from pkgutil import iter_modules
from typing import ClassVar

import numpy as np

# Kind ids are u32 on the GPU; 0 is the kind of a zeroed record, which no kind has.
KIND_MAX = 2**32 - 1


class ParameterError(ValueError):
    """A parameter of a kind is out of its documented range; `parameter` names it. Each family
    raises its own subclass (MaterialError, LightError)."""

    def __init__(self, message: str, parameter: str | None = None) -> None:
        super().__init__(message)
        self.parameter = parameter


def qualified_name(cls: type) -> str:
    """How registration errors name a class: module and qualified name."""
    return f"{cls.__module__}.{cls.__qualname__}"


def import_modules(package: str, path: Iterable[str]) -> None:
    """Import every module of `package` (its `__name__` and `__path__`), so that what a new module
    declares registers itself."""
    for module in iter_modules(path):
        import_module(f"{package}.{module.name}")


class KindRegistry:
    """The classes of one family (materials, lights) by kind id. `check(cls, where)` raises TypeError
    for what else a kind of the family must declare; WGSL names a kind <FAMILY>_<kind_name>."""

    def __init__(self, family: str, check: Callable[[type, str], None]) -> None:
        self.family = family
        self.check = check
        self._classes: dict[int, type] = {}

    def classes(self) -> tuple[type, ...]:
        """Every registered kind, in id order."""
        return tuple(self._classes[kind] for kind in sorted(self._classes))

    def lookup(self, kind: int) -> type:
        """The class registered for `kind`."""
        if kind not in self._classes:
            raise ValueError(f"no {self.family} kind {kind} is registered; the kinds are {self.registered()}")
        return self._classes[kind]

    def import_package(self, package: str, path: Iterable[str]) -> dict[str, type]:
        """Import every module of the family's `package` (its `__name__` and `__path__`), so that a
        class in a new module registers itself, and return every kind by class name, which the
        package exports (and wgputrace.scene and wgputrace after it)."""
        import_modules(package, path)
        return {cls.__name__: cls for cls in self.classes()}

    def registered(self) -> str:
        return ", ".join(f"{cls.kind} ({cls.__name__})" for cls in self.classes())

    def register(self, cls: type) -> None:
        where = qualified_name(cls)
        kind = cls.kind
        if isinstance(kind, bool) or not isinstance(kind, int) or not 1 <= kind <= KIND_MAX:
            raise TypeError(f"{where}: kind must be an int in [1, {KIND_MAX}], got {kind!r}")
        taken = self._classes.get(kind)
        if taken is not None:
            raise TypeError(
                f"{where}: {self.family} kind {kind} is already {qualified_name(taken)}'s; "
                f"the kinds are {self.registered()}"
            )
        cls.kind_name = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", cls.__name__).upper()
        namesake = next((other for other in self._classes.values() if other.kind_name == cls.kind_name), None)
        if namesake is not None:
            raise TypeError(
                f"{where}: WGSL constant {self.family.upper()}_{cls.kind_name} is already kind {namesake.kind} "
                f"({qualified_name(namesake)}); rename the class"
            )
        self.check(cls, where)
        self._classes[kind] = cls


class Kind:
    """The base of a family's base class (Material, Light), which sets `registry` and
    `parameter_error`, says how errors name an object (`label`) and is a dataclass."""

    registry: ClassVar[KindRegistry]
    # what `checked_parameters` raises for a bad value
    parameter_error: ClassVar[type[ParameterError]]
    # the class name in upper snake case, set on registration: WGSL names the kind
    # <FAMILY>_<kind_name> (MATERIAL_DIFFUSE, LIGHT_POINT_LIGHT)
    kind_name: ClassVar[str]

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:
            cls.registry.register(cls)

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
        except self.parameter_error:
            object.__setattr__(self, key, previous)
            raise
        for parameter, normalized in checked.items():
            object.__setattr__(self, parameter, normalized)
        object.__setattr__(self, "version", self.version + 1)

    @classmethod
    def parameter_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls) if f.name != "name")

    def checked_parameters(self) -> dict[str, object]:
        """Every parameter validated and normalized, or `parameter_error` naming the first bad one."""
        raise NotImplementedError

    @property
    def label(self) -> str:
        """How errors name the object ("material 'floor'", "PointLight 'bulb'")."""
        raise NotImplementedError

    def check_number(self, parameter: str, value, *, low: float, high: float, low_inclusive: bool = True) -> float:
        """A finite number in [low, high] (or (low, high] when low_inclusive is false); the error
        prints the bounds as given (0 or 0.0)."""
        bracket = "[" if low_inclusive else "("
        message = f"{self.label}: {parameter} must be in {bracket}{low}, {high}], got {value!r}"
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise self.parameter_error(message, parameter) from None
        below = number < low if low_inclusive else number <= low
        if not math.isfinite(number) or below or number > high:
            raise self.parameter_error(message, parameter)
        return number


def rgb_values(value) -> np.ndarray | None:
    """An RGB parameter as 3 float64 (one number is grey), or None where it is not that many numbers;
    each family's `check_color` says what is wrong with it."""
    try:
        rgb = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        return None
    if rgb.size == 1:
        rgb = np.repeat(rgb, 3)
    return rgb if rgb.size == 3 else None


def finite_non_negative(rgb: np.ndarray) -> bool:
    return bool(np.all(np.isfinite(rgb)) and not np.any(rgb < 0))


def mitsuba_rgb(value) -> dict:
    """An RGB value as a Mitsuba 3 dict entry."""
    return {"type": "rgb", "value": [float(v) for v in value]}
