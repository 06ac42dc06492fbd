"""Every light kind besides emissive triangles, one module each (light.py says what a kind declares).

Each module of this package is imported here, so a class in a new module registers itself and is
exported from this package, from wgputrace.scene and from wgputrace under its class name."""

from importlib import import_module
from pkgutil import iter_modules

from .light import Light, LightError, LightShader, light_class, light_classes

for _module in iter_modules(__path__):
    import_module(f"{__name__}.{_module.name}")

# every kind by class name, for the packages above to export
KINDS = {cls.__name__: cls for cls in light_classes()}
globals().update(KINDS)

__all__ = ["Light", "LightError", "LightShader", "light_class", "light_classes", *KINDS]
