"""The four materials; each file documents its parameters and its Mitsuba 3 equivalent."""

from .diffuse import Diffuse
from .emitter import Emitter
from .glass import Glass
from .glossy import Glossy
from .material import Material, MaterialError, MaterialKind

__all__ = ["Diffuse", "Emitter", "Glass", "Glossy", "Material", "MaterialError", "MaterialKind"]
