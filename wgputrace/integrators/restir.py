"""ReSTIR's direct light (Bitterli et al. 2020) at the first vertex of the path tracer's paths:
light candidates resampled by their unshadowed contribution at every pixel (a pre-pass before each
sample of the whole image), then each pixel's reservoir combined with its neighbours', one shadow
ray for the survivor (shaders/integrators/restir/). The vertices after the first take their light
as "mis" does. Scenes that do not select it compile none of it.

Where reservoirs are shared (RESERVOIR_NEIGHBOURS > 0), a pass takes one sample of each pixel after
the pre-pass made that sample's reservoirs: no path regeneration. With RESERVOIR_HISTORY_CAP > 0
and no neighbours, render_frame's frames over the whole image (its G-buffer variant) keep each
pixel's reservoir for the next frame, which combines it with its own where the camera alone moved
(temporal_reservoirs.wgsl). The viewer's bands and subsets trace part of the image: there a vertex
keeps its own candidates, as everywhere by default."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from ..gpu.bindings import STORAGE_READ_WRITE, Binding
from ..gpu.layout import RESERVOIR_RECEIVER, RESERVOIR_RECORD
from .integrator import PixelArray, register
from .path_tracer import GENERATED_FIRST_VERTEX_LIGHT, PathTracer, path_tracer

if TYPE_CHECKING:
    from ..kernels.variant import KernelVariant

# Each pixel's reservoir from the pre-pass and the surface point it was resampled for, where
# reservoirs are shared (`with_overrides`): two arrays, so that neither passes a device's largest
# storage binding before the other would (64 + 32 bytes a pixel).
RESERVOIRS = PixelArray(Binding("restir_reservoirs", STORAGE_READ_WRITE, RESERVOIR_RECORD), RESERVOIR_RECORD.size // 4)
RECEIVERS = PixelArray(
    Binding("restir_receivers", STORAGE_READ_WRITE, RESERVOIR_RECEIVER), RESERVOIR_RECEIVER.size // 4
)


# Neighbours' reservoirs each first vertex combines with its own (the override RESERVOIR_NEIGHBOURS),
# measured by `python -m bench.restir`: on lavapipe the pre-pass and the combination cost more than
# the variance they remove on every scene measured, so by default a vertex keeps its own candidates
# and no pre-pass runs. `shader_overrides={"RESERVOIR_NEIGHBOURS": 3}` shares them.
RESERVOIR_NEIGHBOURS = 0

# Frames of candidates the previous frame's reservoir counts as at most, where render_frame keeps
# them (the override RESERVOIR_HISTORY_CAP; 0: it keeps none), measured by `python -m
# bench.restir_frames`: the moving picture accumulates frames into each pixel's history, and frames
# that share their light samples are correlated, so its error at equal time per frame was no lower
# with them on any scene measured (bench/README.md) though each frame alone is less noisy. By
# default render_frame keeps no reservoir and allocates none; `shader_overrides=
# {"RESERVOIR_HISTORY_CAP": 20}` keeps them (Bitterli et al.'s 20).
RESERVOIR_HISTORY_CAP = 0


@dataclass(frozen=True)
class Restir(PathTracer):
    def with_overrides(self, overrides: Mapping[str, float]) -> Restir:
        """With neighbours (the override RESERVOIR_NEIGHBOURS), the pre-pass's reservoirs; else,
        with RESERVOIR_HISTORY_CAP > 0, the reservoirs render_frame keeps from frame to frame. A
        scene rendered as shipped allocates none."""
        if overrides.get("RESERVOIR_NEIGHBOURS", RESERVOIR_NEIGHBOURS) > 0:
            return replace(self, pixel_arrays=(RESERVOIRS, RECEIVERS))
        if overrides.get("RESERVOIR_HISTORY_CAP", RESERVOIR_HISTORY_CAP) > 0:
            return replace(self, frame_arrays=(RESERVOIRS, RECEIVERS))
        return self

    def shares(self, variant: KernelVariant) -> bool:
        """Whether `variant`'s kernel shares reservoirs between neighbours (or makes them for that,
        the pre-pass): kernels over the whole image, with neighbours."""
        neighbours = variant.constants.get("RESERVOIR_NEIGHBOURS", RESERVOIR_NEIGHBOURS)
        return neighbours > 0 and not (variant.rows or variant.subset)

    def uses_prepass(self, variant: KernelVariant) -> bool:
        return super().uses_prepass(variant) and self.shares(variant)

    def keeps_reservoirs(self, variant: KernelVariant) -> bool:
        """Whether `variant`'s kernel keeps each pixel's reservoir for the next frame: render_frame's
        kernel over the whole image (the G-buffer variant), where no neighbours share them."""
        return bool(self.frame_arrays) and variant.gbuffer and not (variant.rows or variant.subset)

    def files(self, variant: KernelVariant) -> dict[str, str]:
        """The resampled first vertex, with the vertex's own reservoir, shared ones or its own and
        the previous frame's."""
        reservoir = "own_reservoir"
        if self.shares(variant):
            reservoir = "shared_reservoirs"
        elif self.keeps_reservoirs(variant):
            reservoir = "temporal_reservoirs"
        text = super().files(variant)[GENERATED_FIRST_VERTEX_LIGHT]
        return {GENERATED_FIRST_VERTEX_LIGHT: f'{text}//! include "integrators/restir/{reservoir}.wgsl"\n'}


RESTIR = register(
    path_tracer(
        "restir",
        "path tracing whose first vertex resamples light candidates by their contribution and shares them "
        "with its neighbours (ReSTIR), MIS after it",
        "mis",
        kind=Restir,
        constants=(("RESERVOIR_NEIGHBOURS", RESERVOIR_NEIGHBOURS), ("RESERVOIR_HISTORY_CAP", RESERVOIR_HISTORY_CAP)),
        first_vertex_light="integrators/restir/resampled_direct_light.wgsl",
        prepass_entry="integrators/restir/candidates.wgsl",
    )
)
