"""The GPU resources of an optional bind group (the lights group, the shading group's textures),
kept in step with a SceneMirror's arrays: each made while the scene needs it and freed when it no
longer does, uploaded only where an edit changed it (counted like the scene's buffers), and a
`generation` that changes whenever a resource was made anew or freed, so the group is rebound."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..gpu.device import GpuContext
from ..gpu.float_texture import FloatTexture
from ..gpu.tracked_buffer import TrackedBuffer, UploadCount


class GroupResources:
    """Subclasses name their bindings (`BINDINGS`: the mirror's array label -> binding name) and make
    each resource (`_create`)."""

    BINDINGS: Mapping[str, str] = {}

    def __init__(self, context: GpuContext) -> None:
        self.context = context
        self.buffers: dict[str, TrackedBuffer | FloatTexture] = {}
        self.generation = 0

    def _create(self, name: str, data: np.ndarray) -> TrackedBuffer | FloatTexture:
        raise NotImplementedError

    def _sync(self, arrays: Mapping[str, np.ndarray], changes: Mapping[str, np.ndarray]) -> None:
        """Keep exactly the resources of `arrays` (label -> records), uploading the rows `changes` names."""
        for buffer in self.buffers.values():
            buffer.uploads = UploadCount()
        for name in [name for name in self.buffers if name not in arrays]:
            buffer = self.buffers.pop(name)
            (buffer if isinstance(buffer, FloatTexture) else buffer.buffer).destroy()
            self.generation += 1
        for name, data in arrays.items():
            generation = getattr(self.buffers.get(name), "generation", None)
            if name not in self.buffers:
                self.buffers[name] = self._create(name, data)
            elif name in changes:
                self.buffers[name].upload(data, changes[name])
            if self.buffers[name].generation != generation:
                self.generation += 1

    @property
    def resources(self) -> dict[str, object]:
        """What the group binds, by binding name."""
        return {self.BINDINGS[name]: buffer.resource for name, buffer in self.buffers.items()}
