"""Host/GPU struct layouts, each defined once: a field list becomes both a numpy structured dtype
and the WGSL struct text, with WGSL's alignment rules applied in one place so padding cannot drift."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

# WGSL type -> (numpy scalar, component count, alignment, size) under WGSL's host-shareable rules.
_TYPES = {
    "f32": ("<f4", 1, 4, 4),
    "u32": ("<u4", 1, 4, 4),
    "i32": ("<i4", 1, 4, 4),
    "vec2<f32>": ("<f4", 2, 8, 8),
    "vec2<u32>": ("<u4", 2, 8, 8),
    "vec3<f32>": ("<f4", 3, 16, 12),
    "vec3<u32>": ("<u4", 3, 16, 12),
    "vec4<f32>": ("<f4", 4, 16, 16),
    "vec4<u32>": ("<u4", 4, 16, 16),
}


def _round_up(value: int, alignment: int) -> int:
    return (value + alignment - 1) // alignment * alignment


@dataclass(frozen=True)
class GpuStruct:
    name: str
    fields: tuple[tuple[str, str], ...]
    doc: str = ""

    @cached_property
    def offsets(self) -> tuple[int, ...]:
        offset, offsets = 0, []
        for _, wgsl_type in self.fields:
            _, _, align, size = _TYPES[wgsl_type]
            offset = _round_up(offset, align)
            offsets.append(offset)
            offset += size
        return tuple(offsets)

    @cached_property
    def alignment(self) -> int:
        return max(_TYPES[t][2] for _, t in self.fields)

    @cached_property
    def size(self) -> int:
        """Struct size and array stride: the end of the last field rounded up to the alignment."""
        last_offset, (_, last_type) = self.offsets[-1], self.fields[-1]
        return _round_up(last_offset + _TYPES[last_type][3], self.alignment)

    @cached_property
    def dtype(self) -> np.dtype:
        formats = []
        for _, wgsl_type in self.fields:
            scalar, count, _, _ = _TYPES[wgsl_type]
            formats.append(scalar if count == 1 else (scalar, (count,)))
        return np.dtype(
            {
                "names": [n for n, _ in self.fields],
                "formats": formats,
                "offsets": list(self.offsets),
                "itemsize": self.size,
            }
        )

    def wgsl(self) -> str:
        lines = [f"// {self.doc}"] if self.doc else []
        lines.append(f"struct {self.name} {{")
        lines += [f"    {name}: {wgsl_type}," for name, wgsl_type in self.fields]
        lines.append("}")
        return "\n".join(lines)

    def zeros(self, count: int) -> np.ndarray:
        return np.zeros(count, dtype=self.dtype)


TRIANGLE = GpuStruct(
    "Triangle",
    (("v0", "vec3<f32>"), ("material", "u32"), ("v1", "vec3<f32>"), ("v2", "vec3<f32>")),
    "One flat triangle: its corners and the index of its material (never a copy of it).",
)
BVH_NODE = GpuStruct(
    "BvhNode",
    (("bounds_min", "vec3<f32>"), ("left_or_first", "u32"), ("bounds_max", "vec3<f32>"), ("triangle_count", "u32")),
    "32-byte BVH node: interior (count 0) -> left child, right = left + 1; leaf -> first triangle.",
)
# What the GPU traverses (`WideBVH`): a record per 4-wide node, its children's boxes by axis (min_x
# of the four children in one vec4, ...), seven texels where four boxes with a word beside each
# would take eight, and one word per child (leaf, record or empty, as `collapse` encodes them).
WIDE_BVH_NODE = GpuStruct(
    "WideBvhNode",
    (
        *((f"min_{axis}", "vec4<f32>") for axis in "xyz"),
        *((f"max_{axis}", "vec4<f32>") for axis in "xyz"),
        ("children", "vec4<u32>"),
    ),
    "Up to four children of a 4-wide BVH node: their boxes by axis, and one word each (see `WideBVH`).",
)
MATERIAL = GpuStruct(
    "Material",
    (
        ("color", "vec3<f32>"),
        ("kind", "u32"),
        ("alpha", "f32"),
        ("ior", "f32"),
        ("metallic", "f32"),
        ("spec_trans", "f32"),
        ("absorption", "vec3<f32>"),
        ("clearcoat", "f32"),
        ("clearcoat_gloss", "f32"),
        ("sheen", "f32"),
        ("sheen_tint", "f32"),
        ("anisotropic", "f32"),
    ),
    "color: albedo, Fresnel tint, transmission tint or emitted radiance, by kind; spec_trans, clearcoat, "
    "clearcoat_gloss, sheen, sheen_tint, anisotropic: Principled's; absorption: sigma_a inside (`Material.absorption`), "
    "read only in kernels for scenes with an absorbing material.",
)
FRAME = GpuStruct(
    "Frame",
    (
        ("camera_position", "vec3<f32>"),
        ("width", "u32"),
        ("camera_right", "vec3<f32>"),
        ("height", "u32"),
        ("camera_up", "vec3<f32>"),
        ("max_depth", "u32"),
        ("camera_forward", "vec3<f32>"),
        ("node_count", "u32"),
        ("light_count", "u32"),
        ("light_weight_total", "f32"),
        ("aperture_radius", "f32"),
        ("focus_distance", "f32"),
    ),
    "Per-frame values; the camera's fields as its kind writes them (`Sensor.fill_frame`): for the "
    "perspective kinds camera_right and camera_up span half the image plane at distance 1.",
)
ACCUMULATED_PIXEL = GpuStruct(
    "AccumulatedPixel",
    (("sum", "vec4<f32>"), ("compensation", "vec4<f32>")),
    "Kahan-compensated sum of a pixel's samples; sum.w counts its non-finite samples, compensation.w "
    "those the driver's loop budget may have cut short (both dropped).",
)
GBUFFER_PIXEL = GpuStruct(
    "GBufferPixel",
    (
        ("normal", "vec3<f32>"),
        ("depth", "f32"),
        ("albedo", "vec3<f32>"),
        ("surface", "u32"),
        ("motion", "vec2<f32>"),
        ("previous_depth", "f32"),
        ("object", "u32"),
    ),
    "What the ray through a pixel's centre first hits (write_gbuffer): the shading normal facing the "
    "camera, the distance the camera's ray travels to it (0: nothing hit), the material's colour, the "
    "surface (material index + 1; 0: nothing hit), the motion from this frame's raster position to "
    "the previous frame's, the distance from the previous camera (0: that camera did not see the "
    "point) and the object (the shape's index in Scene.shapes, or their count + the instance's index; "
    "0 where nothing was hit).",
)
# Where a moving object's points were at the previous frame (ObjectMotion in render/object_motion.py
# writes them): bound only in the G-buffer variant, declared by its hook.
OBJECT_MOTION = GpuStruct(
    "ObjectMotion",
    (*((f"previous_from_current{row}", "vec4<f32>") for row in range(3)), ("object", "u32")),
    "An object's previous transform times the inverse of its current one (rows of the 3x4 affine "
    "part; the identity where it did not move), and its id (GBufferPixel.object).",
)

LIGHT = GpuStruct(
    "Light",
    (("triangle", "u32"), ("alias_index", "u32"), ("threshold", "f32")),
    "A light in an alias table: keep this entry when u < threshold, else take entry `alias_index`. "
    "`triangle`: an emissive triangle's index, or a light source (`LIGHT_SOURCE_FLAG`'s encoding).",
)
# A light that is not a triangle nor the environment (a `Light`): what its kind's WGSL reads.
LIGHT_SOURCE = GpuStruct(
    "LightSource",
    (
        ("position", "vec3<f32>"),
        ("kind", "u32"),
        ("direction", "vec3<f32>"),
        ("probability", "f32"),
        ("emission", "vec3<f32>"),
        ("cos_outer", "f32"),
        ("cos_inner", "f32"),
        ("cone", "f32"),
        ("angle_outer", "f32"),
        ("inverse_transition", "f32"),
    ),
    "A point, spot, directional or sun light, its fields as its `Light` kind fills them; "
    "probability: the light sampler's chance of choosing it.",
)
# The lights group's parameters (`lights_group`): the environment's, so that an edit of
# its intensity, rotation or visibility uploads this struct only, and how many light sources there are.
LIGHTING = GpuStruct(
    "Lighting",
    (
        ("environment_radiance", "vec3<f32>"),
        ("environment_visible", "u32"),
        ("environment_rotation", "vec2<f32>"),
        ("environment_probability", "f32"),
        ("source_count", "u32"),
        ("environment_size", "vec2<u32>"),
        ("scene_center", "vec3<f32>"),
        ("scene_radius", "f32"),
    ),
    "environment_radiance: a constant environment's radiance, a map's intensity; rotation: (cos, sin) "
    "of the turn about +y; size: the map's width and height; scene_center, scene_radius: the scene's "
    "bounding sphere where distant lights need it (their power crosses it, light paths start on it).",
)

# An instance as the two-level traversal reads it (`render/instance_records.py`), in the top-level
# BVH's order: world to object (the rays going in) and object to world (hit triangles, normals and
# tangents coming out) as the rows of 3x4 matrices, its mesh's bottom-level root record, and the
# slot its triangles' hit words carry (0 for the scene's own shapes, whose matrices are unused).
INSTANCE = GpuStruct(
    "Instance",
    (
        *((f"world_to_object{row}", "vec4<f32>") for row in range(3)),
        *((f"object_to_world{row}", "vec4<f32>") for row in range(3)),
        ("root", "u32"),
        ("slot", "u32"),
    ),
    "One placement of a mesh: its matrices' rows, its bottom-level BVH's root record, its hit-word slot.",
)

# Shading attributes are stored once per vertex, not per corner: a smooth mesh shares each vertex
# among about six triangles, whose corners held a copy each (`python -m bench.attribute_memory`). A triangle names its three vertices (TRIANGLE_VERTICES, in
# the triangles' BVH order); each attribute is its own array of vertex records, bound only for
# scenes that have it (`shading_group`), so smooth scenes without textures and textured ones
# without normals pay only for theirs. `shared_vertices` makes the vertices: corners whose
# attributes are equal bit for bit are one vertex.
TRIANGLE_VERTICES = GpuStruct(
    "TriangleVertices",
    (("v0", "u32"), ("v1", "u32"), ("v2", "u32")),
    "The indices of a triangle's corners in the vertex arrays (VERTEX_NORMAL and its siblings).",
)
# f32 components rather than a vec3, whose 16-byte alignment would pad every record by a third.
VERTEX_NORMAL = GpuStruct(
    "VertexNormal",
    (("x", "f32"), ("y", "f32"), ("z", "f32")),
    "A vertex's shading normal (unit length; zero: the triangles sharing it shade flat).",
)
VERTEX_UV = GpuStruct(
    "VertexUv",
    (("uv", "vec2<f32>"),),
    "A vertex's texture coordinates (glTF's: v down), zero where its shape has none.",
)
# Bound in textured scenes, one zero record unless a material reads a normal map.
VERTEX_TANGENT = GpuStruct(
    "VertexTangent",
    (("tangent", "vec4<f32>"),),
    "A vertex's tangent for normal maps: xyz along dP/du, w the bitangent's sign (glTF's TANGENT).",
)
# glTF's COLOR_0, OBJ's `v x y z r g b`; bound only in scenes where some shape has them.
VERTEX_COLOR = GpuStruct(
    "VertexColor",
    (("color", "vec4<f32>"),),
    "A vertex's linear RGBA colour, which multiplies its material's colour and alpha; white where its shape has none.",
)
# One texture's rectangle in the texture atlas (`pack_atlas`) and how it is looked up.
TEXTURE = GpuStruct(
    "Texture",
    (
        ("transform_u", "vec3<f32>"),
        ("wrap_s", "u32"),
        ("transform_v", "vec3<f32>"),
        ("wrap_t", "u32"),
        ("origin", "vec2<u32>"),
        ("size", "vec2<u32>"),
        ("srgb", "u32"),
    ),
    "u' = dot(transform_u, (u, v, 1)), v' likewise (KHR_texture_transform); wrap modes as "
    "`WRAP_MODES` indexes them; the texels at origin, size in the atlas; srgb: 1 "
    "where its colour channels are sRGB bytes to decode.",
)
# Which textures a material reads (an index into the TEXTURE records, NO_TEXTURE for none), one
# record per material, and the parameters that only textured scenes need.
MATERIAL_TEXTURES = GpuStruct(
    "MaterialTextures",
    (
        ("base_color", "u32"),
        ("metallic_roughness", "u32"),
        ("normal", "u32"),
        ("alpha", "f32"),
        ("alpha_mode", "u32"),
        ("alpha_cutoff", "f32"),
        ("double_sided", "u32"),
        ("emission", "u32"),
        ("emitted", "vec3<f32>"),
        ("normal_scale", "f32"),
        ("anisotropy_rotation", "f32"),
    ),
    "A material's textures (NO_TEXTURE: none) and its alpha (x the base colour texture's); "
    "alpha_mode as `ALPHA_MODES` numbers them, its cutoff, and 0 for a single-sided surface "
    "(`surface_blocks`); the radiance it emits (x the emission texture's: `surface_emission`); the "
    "normal texture's strength (`mapped_normal`), in the padding after `emitted`; the angle of the "
    "anisotropy's direction from the tangent (`surface_frame`).",
)

# The restir integrator's reservoir of each pixel (shaders/integrators/resampled_direct_light.wgsl),
# kept from one sample of the pixel to the next, and the surface point it was resampled for.
RESERVOIR_RECORD = GpuStruct(
    "ReservoirRecord",
    (
        ("point", "vec3<f32>"),
        ("light", "u32"),
        ("normal", "vec3<f32>"),
        ("kind", "u32"),
        ("radiance", "vec3<f32>"),
        ("weight", "f32"),
        ("density", "f32"),
    ),
    "A light sample kept in a reservoir: the light point (for a distant light, the unit direction "
    "towards it), the light table's word of its light, the light's normal there, whether it is "
    "distant (bit 0) and a delta light (bit 1), its radiance, its unbiased contribution weight W "
    "(per unit area of light for a light at a finite distance), and for a distant light the light "
    "sampler's density of its direction (the same from every receiver).",
)
RESERVOIR_RECEIVER = GpuStruct(
    "ReservoirReceiver",
    (
        ("point", "vec3<f32>"),
        ("triangle", "u32"),
        ("towards_viewer", "vec3<f32>"),
        ("count", "f32"),
    ),
    "The surface point a reservoir was resampled for: the point, its triangle (NO_TRIANGLE: the "
    "reservoir is empty), the unit direction back along the camera's ray, and how many candidates "
    "the reservoir stands for (its confidence M).",
)

ALL_STRUCTS = (
    TRIANGLE,
    BVH_NODE,
    WIDE_BVH_NODE,
    MATERIAL,
    FRAME,
    ACCUMULATED_PIXEL,
    GBUFFER_PIXEL,
    LIGHT,
    LIGHT_SOURCE,
    LIGHTING,
    TRIANGLE_VERTICES,
    RESERVOIR_RECORD,
    RESERVOIR_RECEIVER,
)
# The per-vertex attribute records, each declared by the hook that reads it.
VERTEX_STRUCTS = (VERTEX_NORMAL, VERTEX_UV, VERTEX_TANGENT, VERTEX_COLOR)
