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
from ..gpu.light_dispatch import LightFeatures
from ..gpu.tracked_buffer import TrackedBuffer
from ..scene.lights.environment import ENVIRONMENT_MAP
from .group_resources import GroupResources
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


class LightBuffers(GroupResources):
    """The lights group's resources for a mirror's light features."""

    BINDINGS = BINDINGS

    def __init__(self, context: GpuContext, mirror: SceneMirror) -> None:
        super().__init__(context)
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
        arrays = _arrays(mirror)
        self._sync({name: arrays[name] for name in needed(mirror.light_features)}, changes)
