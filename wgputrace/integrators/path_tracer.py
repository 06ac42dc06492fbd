"""The unidirectional path tracer, one kernel for its three estimators of direct light (the
override INTEGRATOR picks one): "bsdf" (BSDF sampling only), "nee" (next-event estimation only)
and "mis" (both, weighted by the power heuristic), each with a band-of-rows kernel for the viewer.
Its generated file says how a path's first vertex takes its direct light: as every other vertex
here, by resampling under the restir integrator (`wgputrace.integrators.restir`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..kernels.structs import ESTIMATORS
from .integrator import Integrator, register

if TYPE_CHECKING:
    from ..kernels.variant import KernelVariant

GENERATED_FIRST_VERTEX_LIGHT = "generated/first_vertex_light.wgsl"

_DESCRIPTIONS = {
    "bsdf": "path tracing, light found by BSDF sampling alone",
    "nee": "path tracing with next-event estimation alone",
    "mis": "path tracing, BSDF and light sampling weighted by multiple importance sampling",
}


@dataclass(frozen=True)
class PathTracer(Integrator):
    # the WGSL file that defines `first_vertex_light` and RESAMPLES_FIRST_VERTEX
    first_vertex_light: str = "integrators/first_vertex_light.wgsl"

    def files(self, variant: KernelVariant) -> dict[str, str]:
        return {GENERATED_FIRST_VERTEX_LIGHT: f'//! include "{self.first_vertex_light}"\n'}


def path_tracer(
    name: str, description: str, estimator: str, kind: type = PathTracer, constants: tuple = (), **fields
) -> PathTracer:
    """A path tracer (a `kind`) named `name` whose vertices estimate direct light by `estimator`
    (one of ESTIMATORS), with every kernel the path tracer has unless `fields` say otherwise: rows
    for the viewer, a subset for temporal upsampling, several samples a dispatch, absorption and the
    G-buffer; `constants` are override constants besides INTEGRATOR."""
    kernels = {
        "rows_entry": "integrators/path_tracer_rows.wgsl",
        "subset_entry": "integrators/path_tracer_subset.wgsl",
        "regenerates": True,
        "dispatch_samples": (("CPU", 8),),
        "absorbs": True,
        "gbuffer": True,
    }
    overrides = (("INTEGRATOR", ESTIMATORS.index(estimator)), *constants)
    return kind(name, "integrators/path_tracer.wgsl", description, constants=overrides, **(kernels | fields))


for _name in ESTIMATORS:
    register(path_tracer(_name, _DESCRIPTIONS[_name], _name))
