"""The scene's records on the GPU: every array a SceneMirror keeps is an entry of one table
(RECORD_ARRAYS: its name in the mirror, which is also its label, and the bind group and binding it
is bound as), and one mechanism keeps them there (GpuRecords.sync).

A resource exists exactly while the kernel variant's bind groups declare its binding, so a scene
pays only for what it uses; what it is follows from how the binding is declared: texels of
records (TrackedTexels), a storage or parameter buffer (TrackedBuffer), a float texture. An edit
uploads only the rows the mirror says changed, counted (`uploads`); a resource made anew or freed
tells the owner which bind groups to make again.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import wgpu

from ..gpu.bindings import STORAGE_READ, TEXELS, TEXTURE_F32, UNIFORM, BindGroup, Binding
from ..gpu.buffers import PARAMETER_BINDING_LIMIT, PARAMETER_USAGE
from ..gpu.device import GpuContext
from ..gpu.float_texture import FloatTexture
from ..gpu.texels import TrackedTexels
from ..gpu.tracked_buffer import TrackedBuffer, UploadCount
from .object_motion import OBJECT_MOTIONS, TRIANGLE_OBJECTS
from .scene_mirror import (
    ENVIRONMENT_TABLES,
    ENVIRONMENT_TEXELS,
    INSTANCES,
    LIGHT_SOURCES,
    LIGHTING_PARAMETERS,
    LIGHTS,
    MATERIAL_TEXTURES,
    MATERIALS,
    NODES,
    TEXTURE_ATLAS,
    TEXTURES,
    TRIANGLE_LIGHT_DENSITIES,
    TRIANGLES,
    VERTEX_COLORS,
    VERTEX_INDICES,
    VERTEX_NORMALS,
    VERTEX_TANGENTS,
    VERTEX_UVS,
)

# COPY_SRC: what was uploaded can be read back and checked against the host records
_STORAGE_USAGE = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC
_STORAGE_LIMIT = "max-storage-buffer-binding-size"

GpuResource = TrackedBuffer | TrackedTexels | FloatTexture


@dataclass(frozen=True)
class RecordArray:
    """One array of records: `name` in the mirror (and the resource's label), bound as `binding`
    of bind group `group`. `spare`: grow with headroom for additions (arrays that come whole, like
    a map's tables or one record of parameters, do not)."""

    name: str
    group: str
    binding: str
    spare: bool = True


RECORD_ARRAYS = (
    RecordArray(TRIANGLES, "scene", "triangles"),
    RecordArray(NODES, "scene", "nodes"),
    RecordArray(MATERIALS, "scene", "materials"),
    RecordArray(LIGHTS, "scene", "lights"),
    RecordArray(INSTANCES, "scene", "instances"),
    RecordArray(LIGHTING_PARAMETERS, "lights", "lighting", spare=False),
    RecordArray(LIGHT_SOURCES, "lights", "light_sources"),
    RecordArray(ENVIRONMENT_TEXELS, "lights", "environment_map"),
    RecordArray(ENVIRONMENT_TABLES, "lights", "environment_tables", spare=False),
    RecordArray(VERTEX_INDICES, "shading", "triangle_vertices"),
    RecordArray(VERTEX_NORMALS, "shading", "vertex_normals"),
    RecordArray(VERTEX_UVS, "shading", "vertex_uvs"),
    RecordArray(VERTEX_TANGENTS, "shading", "vertex_tangents"),
    RecordArray(VERTEX_COLORS, "shading", "vertex_colors"),
    RecordArray(TEXTURE_ATLAS, "shading", "texture_atlas"),
    RecordArray(TEXTURES, "shading", "textures"),
    RecordArray(MATERIAL_TEXTURES, "shading", "material_textures"),
    RecordArray(TRIANGLE_LIGHT_DENSITIES, "shading", "triangle_light_densities"),
    RecordArray(TRIANGLE_OBJECTS, "pixels", "triangle_objects"),
    RecordArray(OBJECT_MOTIONS, "pixels", "object_motions"),
)
_BY_BINDING = {(array.group, array.binding): array for array in RECORD_ARRAYS}


def _create(context: GpuContext, array: RecordArray, binding: Binding, data: np.ndarray) -> GpuResource:
    if binding.kind == TEXELS:
        return TrackedTexels(context, array.name, data, spare=array.spare)
    if binding.kind == TEXTURE_F32:
        return FloatTexture(context, array.name, data)
    if binding.kind == UNIFORM:
        return TrackedBuffer(
            context, array.name, PARAMETER_USAGE, data, binding_limit=PARAMETER_BINDING_LIMIT, spare=array.spare
        )
    if binding.kind == STORAGE_READ:
        return TrackedBuffer(context, array.name, _STORAGE_USAGE, data, binding_limit=_STORAGE_LIMIT, spare=array.spare)
    raise ValueError(f"record array {array.name!r}: binding {binding.name!r} of kind {binding.kind!r} holds no records")


class GpuRecords:
    """The GPU copies of a mirror's record arrays, by name."""

    def __init__(self, context: GpuContext) -> None:
        self.context = context
        self.resources: dict[str, GpuResource] = {}

    def sync(
        self, arrays: Mapping[str, np.ndarray | None], changes: Mapping[str, np.ndarray], groups: Sequence[BindGroup]
    ) -> set[str]:
        """Keep exactly the arrays that `groups` bind, made from `arrays` (by name) where new and
        uploading the rows `changes` names where kept; free the others. Returns the names of the
        groups whose resources were made anew or freed (to be bound again)."""
        for resource in self.resources.values():
            resource.uploads = UploadCount()
        wanted = {
            array.name: (array, binding)
            for group in groups
            for binding in group.bindings
            if (array := _BY_BINDING.get((group.name, binding.name))) is not None
        }
        regrouped = set()
        for name in [name for name in self.resources if name not in wanted]:
            self.resources.pop(name).destroy()
            regrouped.add(_group_of(name))
        for name, (array, binding) in wanted.items():
            resource = self.resources.get(name)
            if resource is None:
                self.resources[name] = _create(self.context, array, binding, arrays[name])
                regrouped.add(array.group)
            elif name in changes:
                generation = resource.generation
                resource.upload(arrays[name], changes[name])
                if resource.generation != generation:
                    regrouped.add(array.group)
        return regrouped

    def bound_in(self, group: str) -> dict[str, object]:
        """What `group` binds of the records, by binding name."""
        return {
            array.binding: self.resources[array.name].resource
            for array in RECORD_ARRAYS
            if array.group == group and array.name in self.resources
        }

    @property
    def uploads(self) -> dict[str, UploadCount]:
        """Bytes and write calls per array since the last `sync` began, for those it wrote."""
        return {name: resource.uploads for name, resource in self.resources.items() if resource.uploads.calls}

    @property
    def capacity_bytes(self) -> dict[str, int]:
        """Bytes allocated per array (capacity, spare rows included)."""
        return {name: resource.capacity_bytes for name, resource in self.resources.items()}


def _group_of(name: str) -> str:
    return next(array.group for array in RECORD_ARRAYS if array.name == name)
