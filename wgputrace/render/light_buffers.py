"""The lights group's GPU resources (gpu/bindings.py lights_group), following a SceneMirror's light
records: the lighting parameters, the light sources' records, the environment map and its
sampling tables, each allocated only while the scene's lights need it (render/scene_sync.py
LightFeatures) and uploaded only where an edit changed it (counted like the scene's buffers)."""

from __future__ import annotations

import numpy as np
import wgpu

from ..gpu.buffers import PARAMETER_BINDING_LIMIT, PARAMETER_USAGE
from ..gpu.device import GpuContext
from ..gpu.float_texture import FloatTexture
from ..gpu.light_dispatch import ENVIRONMENT_MAP, LightFeatures
from ..gpu.tracked_buffer import TrackedBuffer, UploadCount
from .scene_sync import ENVIRONMENT_TABLES, ENVIRONMENT_TEXELS, LIGHT_SOURCES, LIGHTING_PARAMETERS, SceneMirror

# the mirror's arrays (their labels) by the lights group's binding names
BINDINGS = {
    LIGHTING_PARAMETERS: "lighting",
    LIGHT_SOURCES: "light_sources",
    ENVIRONMENT_TEXELS: "environment_map",
    ENVIRONMENT_TABLES: "environment_tables",
}
_STORAGE = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST


def needed(features: LightFeatures) -> tuple[str, ...]:
    """The arrays a path tracer compiled for `features` binds."""
    if not features.any:
        return ()
    names = [LIGHTING_PARAMETERS]
    if features.kinds:
        names.append(LIGHT_SOURCES)
    if features.environment == ENVIRONMENT_MAP:
        names += [ENVIRONMENT_TEXELS, ENVIRONMENT_TABLES]
    return tuple(names)


def _arrays(mirror: SceneMirror) -> dict[str, np.ndarray | None]:
    return {
        LIGHTING_PARAMETERS: mirror.lighting,
        LIGHT_SOURCES: mirror.sources,
        ENVIRONMENT_TEXELS: mirror.environment_texels,
        ENVIRONMENT_TABLES: mirror.environment_tables,
    }


def _destroy(buffer: TrackedBuffer | FloatTexture) -> None:
    (buffer if isinstance(buffer, FloatTexture) else buffer.buffer).destroy()


class LightBuffers:
    """`generation` changes whenever a resource was made anew, and the lights group must be rebound."""

    def __init__(self, context: GpuContext, mirror: SceneMirror) -> None:
        self.context = context
        self.buffers: dict[str, TrackedBuffer | FloatTexture] = {}
        self.generation = 0
        self.sync(mirror, {})

    def _create(self, name: str, data: np.ndarray) -> TrackedBuffer | FloatTexture:
        if name == ENVIRONMENT_TEXELS:
            return FloatTexture(self.context, name, data)
        if name == LIGHTING_PARAMETERS:
            return TrackedBuffer(
                self.context, name, PARAMETER_USAGE, data, binding_limit=PARAMETER_BINDING_LIMIT, spare=False
            )
        spare = name == LIGHT_SOURCES  # lights are added one at a time; a map's tables come whole
        limit = "max-storage-buffer-binding-size"
        return TrackedBuffer(self.context, name, _STORAGE, data, binding_limit=limit, spare=spare)

    def sync(self, mirror: SceneMirror, changes: dict[str, np.ndarray]) -> None:
        """Make the resources the mirror's features need, free the others, and upload the rows
        `changes` names."""
        for buffer in self.buffers.values():
            buffer.uploads = UploadCount()
        wanted, arrays = needed(mirror.light_features), _arrays(mirror)
        for name in [name for name in self.buffers if name not in wanted]:
            _destroy(self.buffers.pop(name))
            self.generation += 1
        for name in wanted:
            generation = getattr(self.buffers.get(name), "generation", None)
            if name not in self.buffers:
                self.buffers[name] = self._create(name, arrays[name])
            elif name in changes:
                self.buffers[name].upload(arrays[name], changes[name])
            if self.buffers[name].generation != generation:
                self.generation += 1

    @property
    def resources(self) -> dict[str, object]:
        """What the lights group binds, by binding name."""
        return {BINDINGS[name]: buffer.resource for name, buffer in self.buffers.items()}
