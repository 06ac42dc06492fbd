"""Every light kind besides emissive triangles, one module each (`Light` says what a kind declares),
each exported from this package, from wgputrace.scene and from wgputrace under its class name."""

from .light import LIGHT_KINDS, Light, LightError, LightShader, light_class, light_classes

KINDS = LIGHT_KINDS.import_package(__name__, __path__)
globals().update(KINDS)

__all__ = ["Light", "LightError", "LightShader", "light_class", "light_classes", *KINDS]
