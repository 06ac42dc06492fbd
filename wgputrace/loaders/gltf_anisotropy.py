"""glTF's KHR_materials_anisotropy mapped to Principled's anisotropic (Mitsuba 3's `principled`
`anisotropic`) and anisotropy_rotation:

| glTF field                                          | Principled parameter |
|-----------------------------------------------------|----------------------|
| `anisotropyStrength` s (default 0)                  | anisotropic = (1 - alpha / alpha_t) / 0.9, clamped to [0, 1] (`anisotropic_from_strength`) |
| `anisotropyRotation` (radians, default 0)           | anisotropy_rotation (its remainder by 2 pi) |
| `anisotropyTexture`                                 | ignored, with one warning per file |

glTF stretches GGX along the tangent: alpha_t = mix(alpha, 1, s^2) along it, alpha_b = alpha across,
alpha = roughness^2. Mitsuba keeps the product of its two alphas: alpha_u = alpha / aspect along the
tangent, alpha_v = alpha aspect across, aspect = sqrt(1 - 0.9 anisotropic). The mapping gives both
the same ratio alpha_t / alpha_b = 1 / aspect^2 at the material's roughnessFactor (a
metallicRoughnessTexture's roughness is not looked at); Mitsuba's ratio ends at 10 (anisotropic 1),
beyond which glTF's is cut, with a warning. The texture's per-texel direction and strength have no
Principled parameter.
"""

from __future__ import annotations

import math
import warnings

from .errors import SceneLoadWarning

ANISOTROPY = "KHR_materials_anisotropy"
# Mitsuba's aspect = sqrt(1 - ANISOTROPIC_ASPECT_RANGE anisotropic) (principled_anisotropic.wgsl)
ANISOTROPIC_ASPECT_RANGE = 0.9


def anisotropic_from_strength(strength: float, roughness: float) -> float:
    """Mitsuba's `anisotropic` whose alpha_u / alpha_v is glTF's alpha_t / alpha_b at `roughness`,
    unclamped (above 1 where glTF's ratio passes Mitsuba's 10)."""
    alpha = roughness * roughness
    alpha_t = alpha + (1.0 - alpha) * strength * strength
    if alpha_t <= 0.0:
        return 0.0
    return (1.0 - alpha / alpha_t) / ANISOTROPIC_ASPECT_RANGE


class AnisotropyReader:
    """Reads the extension of each material of one file, and warns once per file of the textures it ignores."""

    def __init__(self, reader) -> None:
        self.reader = reader
        self._warned_texture = False

    def parameters(self, extensions: dict, roughness: float, where: str) -> dict[str, float]:
        """Principled's anisotropic and anisotropy_rotation from a material's `extensions` (at
        `where`), none where the file sets no strength above 0; a strength out of [0, 1] or a rotation
        that is not a number is a SceneLoadError naming its JSON path."""
        reader = self.reader
        if ANISOTROPY not in extensions:
            return {}
        block_where = f"{where}.{ANISOTROPY}"
        block = reader.get(extensions, ANISOTROPY, dict, where, {})
        if "anisotropyTexture" in block and not self._warned_texture:
            self._warned_texture = True
            warnings.warn(
                f"{reader.path}: {block_where}.anisotropyTexture ignored (Principled's anisotropy takes no "
                "texture): anisotropyStrength and anisotropyRotation alone are read, here and in the file's other "
                "materials",
                SceneLoadWarning,
                stacklevel=7,
            )
        strength = reader.get(block, "anisotropyStrength", float, block_where, 0.0)
        if not 0.0 <= strength <= 1.0:
            raise reader.fail(f"{block_where}.anisotropyStrength", f"must be in [0, 1], got {strength!r:.40}")
        rotation = reader.get(block, "anisotropyRotation", float, block_where, 0.0)
        if not math.isfinite(rotation):
            raise reader.fail(f"{block_where}.anisotropyRotation", f"must be a finite number, got {rotation!r:.40}")
        anisotropic = anisotropic_from_strength(strength, roughness)
        if anisotropic <= 0.0:
            return {}
        if anisotropic > 1.0:
            warnings.warn(
                f"{reader.path}: {block_where}.anisotropyStrength {strength:g} at roughness {roughness:g} stretches "
                "the highlight more than Mitsuba's anisotropic reaches (alpha ratio 10): anisotropic 1",
                SceneLoadWarning,
                stacklevel=7,
            )
        return {"anisotropic": min(anisotropic, 1.0), "anisotropy_rotation": math.remainder(rotation, math.tau)}
