"""Every material kind, one module each (material.py says what a kind declares).

Each module of this package is imported here, so a class in a new module registers itself and is
exported from this package, from wgputrace.scene and from wgputrace under its class name."""

from importlib import import_module
from pkgutil import iter_modules

from .material import Material, MaterialError, MaterialShader, material_class, material_classes

for _module in iter_modules(__path__):
    import_module(f"{__name__}.{_module.name}")

# every kind by class name, for the packages above to export
KINDS = {cls.__name__: cls for cls in material_classes()}
globals().update(KINDS)

__all__ = ["Material", "MaterialError", "MaterialShader", "material_class", "material_classes", *KINDS]
