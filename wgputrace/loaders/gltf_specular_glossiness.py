"""glTF's KHR_materials_pbrSpecularGlossiness converted to metallic-roughness (`metallic_roughness`),
by the conversion Khronos publishes with the extension (its `convert-between-workflows` example):

| specular-glossiness field                       | metallic-roughness field |
|-------------------------------------------------|--------------------------|
| `diffuseFactor` d (default 1, 1, 1, 1), `specularFactor` s (default 1, 1, 1) | metallicFactor m: the root in [0, 1] of 0.04 m^2 + (D (1 - max(s)) / 0.96 + S - 0.08) m + 0.04 - S, D and S the perceived brightness sqrt(0.299 r^2 + 0.587 g^2 + 0.114 b^2) of d and s (0 where S < 0.04); baseColorFactor rgb: d (1 - max(s)) / 0.96 / (1 - m) blended into (s - 0.04 (1 - m)) / m by m^2, in [0, 1]; a = d's alpha |
| `glossinessFactor` g (default 1)                | roughnessFactor 1 - g |
| `diffuseTexture`                                | baseColorTexture (x the converted factor: exact where m is 0, as for most dielectrics) |

`specularGlossinessTexture` is ignored with a warning: its per-texel specular colour would need a
new texture of converted texels. One SceneLoadWarning per file says that materials were converted.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from .errors import SceneLoadWarning

SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"
# the Fresnel reflectance at normal incidence that metallic-roughness gives every dielectric
DIELECTRIC_SPECULAR = 0.04
# keeps the conversion's divisions by 1 - metallic and metallic finite (Khronos's epsilon)
_EPSILON = 1e-6
# the perceived brightness of a colour: Khronos's weights of its squared components
_BRIGHTNESS_WEIGHTS = np.array([0.299, 0.587, 0.114])


def _brightness(color: np.ndarray) -> float:
    return float(np.sqrt(_BRIGHTNESS_WEIGHTS @ (color * color)))


def _solve_metallic(diffuse: float, specular: float, one_minus_specular: float) -> float:
    if specular < DIELECTRIC_SPECULAR:
        return 0.0
    a = DIELECTRIC_SPECULAR
    b = diffuse * one_minus_specular / (1.0 - a) + specular - 2.0 * a
    c = a - specular
    root = (-b + math.sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
    return min(max(root, 0.0), 1.0)


def metallic_roughness(extension: dict) -> dict:
    """The `pbrMetallicRoughness` object equivalent to a KHR_materials_pbrSpecularGlossiness object
    (its values already checked: numbers of the right counts)."""
    diffuse = np.asarray(extension.get("diffuseFactor", [1.0, 1.0, 1.0, 1.0]), np.float64)
    specular = np.asarray(extension.get("specularFactor", [1.0, 1.0, 1.0]), np.float64)
    glossiness = float(extension.get("glossinessFactor", 1.0))
    one_minus_specular = 1.0 - float(specular.max())
    metallic = _solve_metallic(_brightness(diffuse[:3]), _brightness(specular), one_minus_specular)
    from_diffuse = diffuse[:3] * (one_minus_specular / (1.0 - DIELECTRIC_SPECULAR) / max(1.0 - metallic, _EPSILON))
    from_specular = (specular - DIELECTRIC_SPECULAR * (1.0 - metallic)) / max(metallic, _EPSILON)
    base = np.clip(from_diffuse + (from_specular - from_diffuse) * metallic * metallic, 0.0, 1.0)
    converted = {
        "baseColorFactor": [*base.tolist(), float(diffuse[3])],
        "metallicFactor": metallic,
        "roughnessFactor": 1.0 - glossiness,
    }
    if "diffuseTexture" in extension:
        converted["baseColorTexture"] = extension["diffuseTexture"]
    return converted


def converted_material(reader, entry: dict, where: str, warned: bool) -> dict:
    """`entry` with its pbrMetallicRoughness converted from the extension's fields (checked here,
    errors naming their JSON path); warns (unless `warned`) that the file's materials are converted."""
    block_where = f"{where}.extensions.{SPECULAR_GLOSSINESS}"
    block = reader.get(entry["extensions"], SPECULAR_GLOSSINESS, dict, f"{where}.extensions")
    reader.numbers(block, "diffuseFactor", 4, block_where, [1.0, 1.0, 1.0, 1.0])
    reader.numbers(block, "specularFactor", 3, block_where, [1.0, 1.0, 1.0])
    glossiness = reader.get(block, "glossinessFactor", float, block_where, 1.0)
    if not 0.0 <= glossiness <= 1.0:
        raise reader.fail(f"{block_where}.glossinessFactor", f"must be in [0, 1], got {glossiness!r:.40}")
    if not warned:
        warnings.warn(
            f"{reader.path}: {SPECULAR_GLOSSINESS}: materials converted to metallic-roughness (Khronos's conversion)",
            SceneLoadWarning,
            stacklevel=6,
        )
    if "specularGlossinessTexture" in block:
        warnings.warn(
            f"{reader.path}: {block_where}.specularGlossinessTexture ignored (its specular colour per texel has no "
            "metallic-roughness texture here); the factors alone are converted",
            SceneLoadWarning,
            stacklevel=6,
        )
    return entry | {"pbrMetallicRoughness": metallic_roughness(block)}
