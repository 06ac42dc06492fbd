"""Host/GPU structs, constants and bind groups of the viewer's kernels (guides, resolve, filter,
present, exposure, box lines), defined once like the renderer's (`GpuStruct`, `BindGroup`): each
struct becomes a numpy dtype and the WGSL of GENERATED_VIEW_STRUCTS, each group its WGSL
declarations and layout. The tone curves' constants are wgputrace.render.display_constants'."""

from __future__ import annotations

from enum import IntEnum

from ..gpu.bindings import (
    STORAGE_READ,
    STORAGE_READ_WRITE,
    STORAGE_TEXTURE,
    TEXTURE_F32,
    TEXTURE_U32,
    UNIFORM,
    VERTEX_FRAGMENT,
    BindGroup,
    Binding,
)
from ..gpu.layout import ACCUMULATED_PIXEL, GpuStruct
from ..render.display_constants import FILTER_ALBEDO_MIN  # noqa: F401 (the viewer's filter floor, named here too)

GENERATED_VIEW_STRUCTS = "generated/view_structs.wgsl"

# Guides store the normal in two 16-bit snorms (`pack_guide`): decoded normals are off by
# at most this much per component (measured bound of the octahedral code at 16 bits, with margin).
GUIDE_NORMAL_ERROR = 1e-4
# ... and the albedo in 8-bit unorms: off by at most half a step.
GUIDE_ALBEDO_ERROR = 0.5 / 255
# Texel formats of the viewer's per-pixel images: linear colour, and the packed guides (`pack_guide`).
IMAGE_FORMAT = "rgba32float"
GUIDE_FORMAT = "rgba32uint"


class ResolveMode(IntEnum):
    """What the resolve kernel writes for the radiance view; the ids are its RESOLVE_* constants."""

    MEAN = 0  # the mean of the samples
    DEMODULATED = 1  # the mean over albedo: the filter's input
    BLENDED = 2  # the mean blended with the filtered image by filter_weight


class View(IntEnum):
    """What the viewer shows; the ids are the resolve kernel's VIEW_* constants."""

    RADIANCE = 0
    NORMAL = 1
    ALBEDO = 2
    DEPTH = 3
    HEAT = 4


RESOLVE_PARAMS = GpuStruct(
    "ResolveParams",
    (
        ("width", "u32"),
        ("height", "u32"),
        ("samples_per_pixel", "u32"),
        ("rows_done", "u32"),
        ("view", "u32"),
        ("mode", "u32"),
        ("depth_scale", "f32"),
        ("heat_log2_max", "f32"),
        ("fallback_width", "u32"),
        ("fallback_height", "u32"),
        ("filter_weight", "f32"),
        ("first_row", "u32"),
    ),
    "What the resolve kernel shows (from row first_row on): pixels of rows < rows_done have samples_per_pixel + 1 samples; "
    "pixels without samples show the fallback image (width 0: none); mode is a RESOLVE_* id.",
)
ATROUS_PARAMS = GpuStruct(
    "AtrousParams",
    (
        ("width", "u32"),
        ("height", "u32"),
        ("step", "u32"),
        ("normal_power", "f32"),
        ("depth_sigma", "f32"),
        ("albedo_sigma", "f32"),
    ),
    "One a-trous pass: the tap spacing and the edge-stop widths.",
)
PRESENT_PARAMS = GpuStruct(
    "PresentParams",
    (
        ("image_width", "u32"),
        ("image_height", "u32"),
        ("target_width", "u32"),
        ("target_height", "u32"),
        ("overlay_x", "u32"),
        ("overlay_y", "u32"),
        ("overlay_visible", "u32"),
        ("exposure", "f32"),
        ("tonemap", "u32"),
        ("auto_exposure", "u32"),
    ),
    "Image and target sizes in pixels, where the overlay sits, the exposure (a factor; with auto_exposure "
    "times MIDDLE_GREY over the measured log average) and the tone curve (a TONEMAP_* id).",
)
EXPOSURE_PARAMS = GpuStruct(
    "ExposureParams",
    (
        ("width", "u32"),
        ("height", "u32"),
        ("blend", "f32"),
        ("restart", "u32"),
    ),
    "The image's size, and how much of the new log average the smoothed one takes (restart: all of it).",
)
BOX_LINES_PARAMS = GpuStruct(
    "BoxLinesParams",
    (
        ("row_x", "vec4<f32>"),
        ("row_y", "vec4<f32>"),
        ("row_z", "vec4<f32>"),
        ("row_w", "vec4<f32>"),
        ("color", "vec4<f32>"),
    ),
    "Rows of the 4x4 world-to-clip matrix of the path tracer's camera, and the line colour.",
)

VIEW_STRUCTS = (RESOLVE_PARAMS, ATROUS_PARAMS, PRESENT_PARAMS, EXPOSURE_PARAMS, BOX_LINES_PARAMS)
# The auto-exposure's state, one vec4 on the GPU: x the smoothed log-average luminance (natural
# log), y 1 once measured.
EXPOSURE_STATE = "vec4<f32>"

# The guides kernel (`guides_kernel`) writes them beside the scene group (group 0).
GUIDES_GROUP = BindGroup("guides", 1, (Binding("guides", STORAGE_TEXTURE, GUIDE_FORMAT),))
RESOLVE_GROUP = BindGroup(
    "resolve",
    0,
    (
        Binding("params", UNIFORM, RESOLVE_PARAMS),
        Binding("accumulation", STORAGE_READ, ACCUMULATED_PIXEL),
        Binding("guides", TEXTURE_U32),
        Binding("fallback", TEXTURE_F32),
        Binding("filtered", TEXTURE_F32),
        Binding("resolved", STORAGE_TEXTURE, IMAGE_FORMAT),
    ),
)
ATROUS_GROUP = BindGroup(
    "atrous",
    0,
    (
        Binding("params", UNIFORM, ATROUS_PARAMS),
        Binding("guides", TEXTURE_U32),
        Binding("source", TEXTURE_F32),
        Binding("filtered_out", STORAGE_TEXTURE, IMAGE_FORMAT),
    ),
)
PRESENT_GROUP = BindGroup(
    "present",
    0,
    (
        Binding("params", UNIFORM, PRESENT_PARAMS),
        Binding("image", TEXTURE_F32),
        Binding("overlay", TEXTURE_F32),
        Binding("exposure_state", STORAGE_READ, EXPOSURE_STATE),
    ),
    VERTEX_FRAGMENT,
)
EXPOSURE_GROUP = BindGroup(
    "exposure",
    0,
    (
        Binding("params", UNIFORM, EXPOSURE_PARAMS),
        Binding("image", TEXTURE_F32),
        Binding("exposure_state", STORAGE_READ_WRITE, EXPOSURE_STATE),
    ),
)
BOX_LINES_GROUP = BindGroup(
    "box_lines",
    0,
    (Binding("params", UNIFORM, BOX_LINES_PARAMS), Binding("endpoints", STORAGE_READ, "vec4<f32>")),
    VERTEX_FRAGMENT,
)


def generated_view_structs() -> str:
    parts = ["// Generated from wgputrace.view.layout: the viewer's host/GPU structs, view ids and tone curves."]
    parts += [struct.wgsl() for struct in VIEW_STRUCTS]
    parts += [f"const VIEW_{view.name}: u32 = {int(view)}u;" for view in View]
    parts += [f"const RESOLVE_{mode.name}: u32 = {int(mode)}u;" for mode in ResolveMode]
    return "\n".join(parts) + "\n"
