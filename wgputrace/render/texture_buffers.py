"""The texture bindings of the shading group (gpu/bindings.py shading_group) as GPU resources,
following a SceneMirror's texture records: the corner texture coordinates, the atlas, the textures'
records and the materials' texture slots, allocated only while a material reads a texture and
uploaded only where an edit changed them (counted like the scene's buffers; the atlas by rows of texels)."""

from __future__ import annotations

import numpy as np
import wgpu

from ..gpu.device import GpuContext
from ..gpu.float_texture import FloatTexture
from ..gpu.tracked_buffer import TrackedBuffer
from .group_resources import GroupResources
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


class TextureBuffers(GroupResources):
    """The shading group's texture resources: all of them while a material reads a texture, none otherwise."""

    BINDINGS = BINDINGS

    def __init__(self, context: GpuContext, mirror: SceneMirror) -> None:
        super().__init__(context)
        self.sync(mirror, {})

    def _create(self, name: str, data: np.ndarray) -> TrackedBuffer | FloatTexture:
        if name == TEXTURE_ATLAS:
            return FloatTexture(self.context, name, data)
        return TrackedBuffer(self.context, name, _STORAGE, data, binding_limit="max-storage-buffer-binding-size")

    def sync(self, mirror: SceneMirror, changes: dict[str, np.ndarray]) -> None:
        """Make the resources a textured scene needs or free them all, and upload the rows
        `changes` names."""
        self._sync(_arrays(mirror) if mirror.textured else {}, changes)
