"""Every light kind besides emissive triangles, one module each (light.py says what a kind declares).

Each module of this package is imported here, so a class in a new module registers itself and is
exported from this package, from wgputrace.scene and from wgputrace under its class name."""

from ..registry import import_modules
from .light import LIGHT_KINDS, Light, LightError, LightShader, light_class, light_classes

import_modules(__name__, __path__)
KINDS = LIGHT_KINDS.by_name()
globals().update(KINDS)

__all__ = ["Light", "LightError", "LightShader", "light_class", "light_classes", *KINDS]
