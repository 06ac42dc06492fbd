"""Every material kind, one module each (`Material` says what a kind declares), each exported from
this package, from wgputrace.scene and from wgputrace under its class name."""

from .material import MATERIAL_KINDS, Material, MaterialError, MaterialShader, material_class, material_classes

KINDS = MATERIAL_KINDS.import_package(__name__, __path__)
globals().update(KINDS)

__all__ = ["Material", "MaterialError", "MaterialShader", "material_class", "material_classes", *KINDS]
