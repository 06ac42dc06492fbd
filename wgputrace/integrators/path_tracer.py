"""The unidirectional path tracer, one kernel for its three estimators of direct light (the
override INTEGRATOR picks one): "bsdf" (BSDF sampling only), "nee" (next-event estimation only)
and "mis" (both, weighted by the power heuristic), each with a band-of-rows kernel for the viewer."""

from __future__ import annotations

from ..kernels.structs import ESTIMATORS
from .integrator import Integrator, register

_DESCRIPTIONS = {
    "bsdf": "path tracing, light found by BSDF sampling alone",
    "nee": "path tracing with next-event estimation alone",
    "mis": "path tracing, BSDF and light sampling weighted by multiple importance sampling",
}

for _index, _name in enumerate(ESTIMATORS):
    register(
        Integrator(
            _name,
            "integrators/path_tracer.wgsl",
            _DESCRIPTIONS[_name],
            rows_entry="integrators/path_tracer_rows.wgsl",
            subset_entry="integrators/path_tracer_subset.wgsl",
            constants=(("INTEGRATOR", _index),),
            regenerates=True,
            dispatch_samples=(("CPU", 8),),
            absorbs=True,
            gbuffer=True,
        )
    )
