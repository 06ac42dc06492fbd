"""The texture bindings of the shading group (gpu/bindings.py shading_group) as GPU resources,
following a SceneMirror's texture records: the corner texture coordinates, the atlas, the textures'
records and the materials' texture slots, allocated only while a material reads a texture and
uploaded only where an edit changed them (counted like the scene's buffers; the atlas by rows of texels)."""

from __future__ import annotations

import numpy as np
import wgpu

from ..gpu.device import GpuContext
from ..gpu.float_texture import FloatTexture
from ..gpu.tracked_buffer import TrackedBuffer, UploadCount
from .scene_sync import (
    CORNER_TANGENTS,
    CORNER_UVS,
    MATERIAL_TEXTURES,
    TEXTURE_ATLAS,
    TEXTURES,
    TRIANGLE_LIGHT_DENSITIES,
    SceneMirror,
)

# the mirror's arrays (their labels) by the shading group's binding names
BINDINGS = {
    CORNER_UVS: "corner_uvs",
    CORNER_TANGENTS: "corner_tangents",
    TEXTURE_ATLAS: "texture_atlas",
    TEXTURES: "textures",
    MATERIAL_TEXTURES: "material_textures",
    TRIANGLE_LIGHT_DENSITIES: "triangle_light_densities",
}
_STORAGE = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST | wgpu.BufferUsage.COPY_SRC


def _arrays(mirror: SceneMirror) -> dict[str, np.ndarray]:
    return {
        CORNER_UVS: mirror.corner_uvs,
        CORNER_TANGENTS: mirror.corner_tangents,
        TEXTURE_ATLAS: mirror.atlas_texels,
        TEXTURES: mirror.texture_records,
        MATERIAL_TEXTURES: mirror.material_textures,
        TRIANGLE_LIGHT_DENSITIES: mirror.triangle_light_densities,
    }


class TextureBuffers:
    """`generation` changes whenever a resource was made anew or freed, and the shading group must
    be rebound."""

    def __init__(self, context: GpuContext, mirror: SceneMirror) -> None:
        self.context = context
        self.buffers: dict[str, TrackedBuffer | FloatTexture] = {}
        self.generation = 0
        self.sync(mirror, {})

    def _create(self, name: str, data: np.ndarray) -> TrackedBuffer | FloatTexture:
        if name == TEXTURE_ATLAS:
            return FloatTexture(self.context, name, data)
        return TrackedBuffer(self.context, name, _STORAGE, data, binding_limit="max-storage-buffer-binding-size")

    def sync(self, mirror: SceneMirror, changes: dict[str, np.ndarray]) -> None:
        """Make the resources a textured scene needs or free them all, and upload the rows
        `changes` names."""
        for buffer in self.buffers.values():
            buffer.uploads = UploadCount()
        if not mirror.textured:
            for buffer in self.buffers.values():
                (buffer if isinstance(buffer, FloatTexture) else buffer.buffer).destroy()
            self.generation += bool(self.buffers)
            self.buffers = {}
            return
        for name, data in _arrays(mirror).items():
            generation = getattr(self.buffers.get(name), "generation", None)
            if name not in self.buffers:
                self.buffers[name] = self._create(name, data)
            elif name in changes:
                self.buffers[name].upload(data, changes[name])
            if self.buffers[name].generation != generation:
                self.generation += 1

    @property
    def resources(self) -> dict[str, object]:
        """What the shading group binds for textures, by binding name (none without textures)."""
        return {BINDINGS[name]: buffer.resource for name, buffer in self.buffers.items()}
