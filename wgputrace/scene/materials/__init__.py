"""Every material kind, one module each (material.py says what a kind declares).

Each module of this package is imported here, so a class in a new module registers itself and is
exported from this package, from wgputrace.scene and from wgputrace under its class name."""

from ..registry import import_modules
from .material import MATERIAL_KINDS, Material, MaterialError, MaterialShader, material_class, material_classes

import_modules(__name__, __path__)
KINDS = MATERIAL_KINDS.by_name()
globals().update(KINDS)

__all__ = ["Material", "MaterialError", "MaterialShader", "material_class", "material_classes", *KINDS]
