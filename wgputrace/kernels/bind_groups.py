"""The bind groups of the kernels that trace a scene, each declared once; a KernelVariant chooses
which of them, and which of their bindings, a kernel declares (`KernelVariant.groups`).

The scene group is what every ray-tracing kernel shares; the lights and shading groups are their
own so that the scene group stays the same with or without them (the viewer's guides read it as
declared). Group indices 4 and 5 need max-bind-groups >= 5 and 6 (`check_scene_size` asks).
"""

from __future__ import annotations

from dataclasses import replace

from ..gpu.bindings import (
    ATOMIC_COUNTERS,
    STORAGE_READ,
    STORAGE_READ_WRITE,
    TEXELS,
    TEXTURE_F32,
    UNIFORM,
    BindGroup,
    Binding,
)
from ..gpu.layout import (
    ACCUMULATED_PIXEL,
    BVH_NODE,
    FRAME,
    GBUFFER_PIXEL,
    INSTANCE,
    LIGHT,
    LIGHT_SOURCE,
    LIGHTING,
    MATERIAL,
    MATERIAL_TEXTURES,
    OBJECT_MOTION,
    TEXTURE,
    TRIANGLE_VERTICES,
    VERTEX_COLOR,
    VERTEX_NORMAL,
    VERTEX_TANGENT,
    VERTEX_UV,
)
from ..scene.lights.environment import ENVIRONMENT_MAP
from .light_dispatch import LightFeatures

# Triangles are texels (TrackedTexels: faster loads on lavapipe); the nodes are declared per
# traversal (`scene_group`): texels of 4-wide records for the BVH, a storage array of boxes for the
# flat list.
SCENE_GROUP = BindGroup(
    "scene",
    0,
    (
        Binding("frame", UNIFORM, FRAME),
        Binding("triangles", TEXELS),
        Binding("nodes", TEXELS),
        Binding("materials", STORAGE_READ, MATERIAL),
        Binding("lights", STORAGE_READ, LIGHT),
    ),
)
_NODES = {"bvh": Binding("nodes", TEXELS), "flat": Binding("nodes", STORAGE_READ, BVH_NODE)}
ACCELERATIONS = tuple(_NODES)


# A scene with instances adds their records (`render/instance_records.py`), read by the two-level
# traversal and by whatever takes a hit triangle to the world (`generated/instancing.wgsl`).
_INSTANCES = Binding("instances", STORAGE_READ, INSTANCE)


def scene_group(acceleration: str, instanced: bool = False) -> BindGroup:
    """The scene group with the nodes as `acceleration`'s traversal reads them, and the instances'
    records where `instanced`."""
    if acceleration not in _NODES:
        raise ValueError(f"acceleration must be one of {ACCELERATIONS}, got {acceleration!r}")
    group = SCENE_GROUP.with_binding(_NODES[acceleration])
    return group.extended(_INSTANCES) if instanced else group


# Each pixel's random state and running sum: what every integrator writes. An integrator's own
# per-pixel arrays (`Integrator.pixel_arrays`) and the denoiser's guides extend it.
PIXELS_GROUP = BindGroup(
    "pixels",
    1,
    (
        Binding("rng_states", STORAGE_READ_WRITE, "vec4<u32>"),
        Binding("accumulation", STORAGE_READ_WRITE, ACCUMULATED_PIXEL),
    ),
)
# The denoiser's guides: two Kahan sums per pixel, the albedo's at 2 * pixel and the normal's at
# 2 * pixel + 1, bound only in the variants that make them.
GUIDE_SUMS = Binding("guide_sums", STORAGE_READ_WRITE, ACCUMULATED_PIXEL)
# The G-buffer of the pixels' centres, the previous frame's camera its motion vectors project
# through, and what moves each object's points back to the previous frame (each world triangle's
# record in object_motions; an instance's is its slot's), bound only in the variants that write it
# (`KernelVariant.gbuffer`).
GBUFFER = Binding("gbuffer", STORAGE_READ_WRITE, GBUFFER_PIXEL)
PREVIOUS_FRAME = Binding("previous_frame", UNIFORM, FRAME)
TRIANGLE_OBJECTS = Binding("triangle_objects", STORAGE_READ, "u32")
OBJECT_MOTIONS = Binding("object_motions", STORAGE_READ, OBJECT_MOTION)
GBUFFER_BINDINGS = (GBUFFER, PREVIOUS_FRAME, TRIANGLE_OBJECTS, OBJECT_MOTIONS)

# The viewer's band of rows: the first row of this dispatch.
BAND_GROUP = BindGroup("band", 2, (Binding("band_first_row", UNIFORM, "u32"),))
# Temporal upsampling's subset of pixels: (stride, offset x, offset y, unused), one pixel of each
# stride x stride block (`KernelVariant.subset`). Index 2 as the band group's: it takes one sample
# per pixel per dispatch, as the bands do.
SUBSET_GROUP = BindGroup("subset", 2, (Binding("pixel_subset", UNIFORM, "vec4<u32>"),))
# How many samples of its pixel each invocation takes in this dispatch, only in the kernels that
# take more than one (`KernelVariant.samples_per_dispatch`). Index 2 as the band group's: the
# viewer's bands take one sample per pixel, so no kernel binds both. Under a loop budget
# (`KernelVariant.loop_budget`) also the samples each pixel still owes, left by a dispatch whose
# budget ran out, and their total (`dispatch_group`).
DISPATCH_GROUP = BindGroup("dispatch", 2, (Binding("dispatch_samples", STORAGE_READ, "u32"),))
_OWED_SAMPLES = (Binding("owed_samples", STORAGE_READ_WRITE, "u32"), Binding("owed_total", ATOMIC_COUNTERS))


def dispatch_group(loop_budget: bool) -> BindGroup:
    """The dispatch group of a kernel taking several samples per dispatch, with the owed samples
    under a loop budget."""
    group = DISPATCH_GROUP
    for binding in _OWED_SAMPLES if loop_budget else ():
        group = group.extended(binding)
    return group


# Rays and lanes counted (`ray_count_hook`), only in the counting variants.
RAY_COUNT_GROUP = BindGroup("ray_count", 3, (Binding("ray_counts", ATOMIC_COUNTERS),))

# The lights besides emissive triangles, each binding only where the scene needs it: the parameters
# (the environment's, the light source count) with any such light, the light sources' records with
# any, the environment map (rgba32float texels, read with textureLoad: float32 filtering is an
# optional feature) and its sampling tables (32-bit words in one buffer) with a map.
LIGHTS_GROUP_INDEX = 4
_LIGHTING = Binding("lighting", UNIFORM, LIGHTING)
_LIGHT_SOURCES = Binding("light_sources", STORAGE_READ, LIGHT_SOURCE)
_ENVIRONMENT_MAP = Binding("environment_map", TEXTURE_F32)
_ENVIRONMENT_TABLES = Binding("environment_tables", STORAGE_READ, "u32")


def lights_group(features: LightFeatures) -> BindGroup:
    """The lights group of a kernel compiled for `features` (which have some light)."""
    if not features.any:
        raise ValueError("a scene lit by emissive triangles alone binds no lights group")
    group = BindGroup("lights", LIGHTS_GROUP_INDEX, (_LIGHTING,))
    if features.kinds:
        group = group.extended(_LIGHT_SOURCES)
    if features.environment == ENVIRONMENT_MAP:
        group = group.extended(_ENVIRONMENT_MAP).extended(_ENVIRONMENT_TABLES)
    return group


# Each triangle's vertices in BVH order (`triangle_vertices` reads them), in every shading group,
# and the vertex normals of scenes with per-vertex normals.
SHADING_GROUP_INDEX = 5
SHADING_GROUP = BindGroup(
    "shading", SHADING_GROUP_INDEX, (Binding("triangle_vertices", STORAGE_READ, TRIANGLE_VERTICES),)
)
_NORMAL_BINDINGS = (Binding("vertex_normals", STORAGE_READ, VERTEX_NORMAL),)
# What textured scenes add to it: the vertex texture coordinates, the atlas (linear rgba32float
# texels read with textureLoad and filtered by hand, as the environment map), the textures'
# rectangles in it, each material's textures, the vertex tangents of normal maps, and the light
# table's weight per unit area of each triangle emitting through a texture record.
_TEXTURE_BINDINGS = (
    Binding("vertex_uvs", STORAGE_READ, VERTEX_UV),
    Binding("vertex_tangents", STORAGE_READ, VERTEX_TANGENT),
    Binding("texture_atlas", TEXTURE_F32),
    Binding("textures", STORAGE_READ, TEXTURE),
    Binding("material_textures", STORAGE_READ, MATERIAL_TEXTURES),
    Binding("triangle_light_densities", STORAGE_READ, "f32"),
)

# What scenes with vertex colours add: the vertex colours.
_VERTEX_COLOR_BINDINGS = (Binding("vertex_colors", STORAGE_READ, VERTEX_COLOR),)


def shading_group(smooth: bool, textured: bool, vertex_colors: bool = False) -> BindGroup:
    """The shading group of a scene with per-vertex normals (`smooth`), textures (`textured`),
    vertex colours (`vertex_colors`) or several; its file is SHADING_GROUP.file in every variant."""
    if not (smooth or textured or vertex_colors):
        raise ValueError("a flat, untextured scene without vertex colours binds no shading group")
    bindings = (
        SHADING_GROUP.bindings
        + (_NORMAL_BINDINGS if smooth else ())
        + (_TEXTURE_BINDINGS if textured else ())
        + (_VERTEX_COLOR_BINDINGS if vertex_colors else ())
    )
    return replace(SHADING_GROUP, bindings=bindings)
