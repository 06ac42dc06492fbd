"""glTF's clearcoat and sheen extensions mapped to Principled's lobes of those names (Mitsuba 3's
`principled` clearcoat and sheen), the nearest Mitsuba parameters to what glTF describes:

| glTF field                                                  | Principled parameter |
|-------------------------------------------------------------|----------------------|
| `KHR_materials_clearcoat.clearcoatFactor` (default 0)        | clearcoat |
| `KHR_materials_clearcoat.clearcoatRoughnessFactor` r (default 0) | clearcoat_gloss = (0.1 - r^2) / 0.099 in [0, 1] (`clearcoat_gloss`) |
| `KHR_materials_sheen.sheenColorFactor` (default 0, 0, 0)     | sheen = its largest component; sheen_tint 0 (white) |

How they differ. glTF's coat is a GGX layer of alpha r^2 with the Fresnel of eta 1.5 that dims the
base beneath it by what it reflects; Mitsuba's is a GTR1 lobe (sharper peak, longer tails) of alpha
lerp(0.1, 0.001, clearcoat_gloss), Schlick's Fresnel about 0.04 (the same eta 1.5), added on top
of the base undimmed, as 0.25 F D G cos_o: a microfacet lobe's F D G / (4 cos_i) at normal
incidence, less by cos_i cos_o elsewhere. The mapping keeps the alpha where Mitsuba's range holds
it (r from 0.0316 to 0.316), the glossiest or roughest coat beyond.
glTF's sheen is a Charlie (inverted Gaussian) lobe of its own colour and roughness over a dimmed
base; Mitsuba's is Burley's colourless (1 - cos_d)^5 grazing term tinted only towards the base
colour, without roughness: its colour's hue and `sheenRoughnessFactor` are lost (the hue with a
warning). Textures of both extensions and `clearcoatNormalTexture` are ignored with a warning each
(Principled's clearcoat and sheen take no textures; Mitsuba's clearcoat has no normal of its own).
"""

from __future__ import annotations

import warnings

from .errors import SceneLoadWarning

CLEARCOAT = "KHR_materials_clearcoat"
SHEEN = "KHR_materials_sheen"
LOBE_EXTENSIONS = (CLEARCOAT, SHEEN)
# Mitsuba's clearcoat GTR1 alpha at clearcoat_gloss 0 and 1
_ROUGHEST_COAT, _GLOSSIEST_COAT = 0.1, 0.001
# Material extensions without a Principled (Mitsuba principled) parameter that means the same, and
# why: what the ignoring warning and a refusal say of them (gltf.UNREAD_EXTENSIONS)
UNMAPPED_MATERIAL_EXTENSIONS = {
    "KHR_materials_specular": (
        "specular strength and colour: Mitsuba's spec_tint tints towards the base colour only",
        "no parameter of Mitsuba's principled means the same",
    ),
}
# the fields of each extension that Principled has no parameter for
_IGNORED = {
    CLEARCOAT: ("clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"),
    SHEEN: ("sheenColorTexture", "sheenRoughnessTexture"),
}


def clearcoat_gloss(roughness: float) -> float:
    """The clearcoat_gloss whose GTR1 alpha is glTF's coat alpha roughness^2, within Mitsuba's range."""
    gloss = (_ROUGHEST_COAT - roughness * roughness) / (_ROUGHEST_COAT - _GLOSSIEST_COAT)
    return min(max(gloss, 0.0), 1.0)


def lobe_parameters(reader, extensions: dict, where: str) -> dict[str, float]:
    """Principled's clearcoat and sheen parameters from a material's `extensions` (at `where`), only
    those the file sets; fields out of [0, 1] are a SceneLoadError naming their JSON path."""
    parameters: dict[str, float] = {}
    blocks = {name: reader.get(extensions, name, dict, where, {}) for name in LOBE_EXTENSIONS if name in extensions}

    def unit(name: str, key: str, default) -> float:
        value = reader.get(blocks[name], key, float, f"{where}.{name}", default)
        if not 0.0 <= value <= 1.0:
            raise reader.fail(f"{where}.{name}.{key}", f"must be in [0, 1], got {value!r:.40}")
        return value

    if CLEARCOAT in blocks:
        parameters["clearcoat"] = unit(CLEARCOAT, "clearcoatFactor", 0.0)
        parameters["clearcoat_gloss"] = clearcoat_gloss(unit(CLEARCOAT, "clearcoatRoughnessFactor", 0.0))
    if SHEEN in blocks:
        color = reader.numbers(blocks[SHEEN], "sheenColorFactor", 3, f"{where}.{SHEEN}", [0.0, 0.0, 0.0])
        for component in color:
            if not 0.0 <= component <= 1.0:
                raise reader.fail(f"{where}.{SHEEN}.sheenColorFactor", f"must be in [0, 1], got {color.tolist()}")
        parameters["sheen"] = float(color.max())
        if color.max() > color.min():
            warnings.warn(
                f"{reader.path}: {where}.{SHEEN}.sheenColorFactor {color.tolist()}: Principled's sheen is "
                f"white (or the base colour's hue): its weight is the largest component, {color.max():g}",
                SceneLoadWarning,
                stacklevel=7,
            )
    for name, block in blocks.items():
        ignored = [key for key in _IGNORED[name] if key in block]
        if ignored:
            warnings.warn(
                f"{reader.path}: {where}.{name}: {', '.join(ignored)} ignored (Principled's clearcoat and sheen "
                "take no textures; Mitsuba's clearcoat has no normal of its own): the factors alone are read",
                SceneLoadWarning,
                stacklevel=7,
            )
    return parameters
