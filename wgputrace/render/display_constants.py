"""WGSL constants that the viewer's passes and the renderer's temporal passes share: the tone curves'
(`image_io.tone_curve`'s, whose numpy curves the shader's must equal) and the demodulation floor
FILTER_ALBEDO_MIN, as GENERATED_DISPLAY_CONSTANTS."""

from __future__ import annotations

from .. import image_io

GENERATED_DISPLAY_CONSTANTS = "generated/display_constants.wgsl"

# The filters divide radiance by the first hit's albedo and multiply it back; albedo channels
# below this (black materials, nothing hit) divide by it instead of by ~0.
FILTER_ALBEDO_MIN = 1e-3


def _wgsl_matrix(name: str, matrix) -> str:
    """A 3x3 numpy matrix (acting on column vectors) as a WGSL constant (mat3x3 takes columns)."""
    columns = ", ".join(f"{value!r}" for value in matrix.T.ravel().tolist())
    return f"const {name}: mat3x3<f32> = mat3x3<f32>({columns});"


def tone_constants() -> list[str]:
    """The tone curves' ids and constants (`image_io.tone_curve`'s), as WGSL."""
    parts = [f"const TONEMAP_{name.upper()}: u32 = {index}u;" for index, name in enumerate(image_io.TONEMAP_OPERATORS)]
    scalars = (
        "MIDDLE_GREY",
        "LOG_AVERAGE_FLOOR",
        "TONE_RADIANCE_MAX",
        "PBR_NEUTRAL_F90",
        "PBR_NEUTRAL_COMPRESSION_START",
    )
    scalars += ("PBR_NEUTRAL_DESATURATION", "AGX_MIN_EV", "AGX_MAX_EV", "AGX_FLOOR", "AGX_DISPLAY_GAMMA")
    parts += [f"const {name}: f32 = {float(getattr(image_io, name))!r};" for name in scalars]
    for name in ("SRGB_TO_REC2020", "REC2020_TO_SRGB", "AGX_INSET", "AGX_OUTSET", "ACES_INPUT", "ACES_OUTPUT"):
        parts.append(_wgsl_matrix(name, getattr(image_io, name)))
    luminance = ", ".join(repr(float(w)) for w in image_io.REC709_LUMINANCE)
    parts.append(f"const REC709_LUMINANCE: vec3<f32> = vec3<f32>({luminance});")
    sigmoid = ", ".join(repr(float(c)) for c in image_io.AGX_SIGMOID)
    parts.append(
        f"const AGX_SIGMOID: array<f32, {len(image_io.AGX_SIGMOID)}> = array<f32, {len(image_io.AGX_SIGMOID)}>({sigmoid});"
    )
    fit = ", ".join(repr(float(c)) for c in image_io.ACES_FIT)
    parts.append(f"const ACES_FIT: array<f32, {len(image_io.ACES_FIT)}> = array<f32, {len(image_io.ACES_FIT)}>({fit});")
    return parts


def display_constants() -> str:
    parts = ["// Generated from wgputrace.render.display_constants: tone curves and the filters' albedo floor."]
    parts.append(f"const FILTER_ALBEDO_MIN: f32 = {FILTER_ALBEDO_MIN!r};")
    parts += tone_constants()
    return "\n".join(parts) + "\n"
