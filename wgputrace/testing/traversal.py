"""The shipped `closest_hit` (of the BVH's traversal or the flat list's) run on numpy rays through
the WGSL harness: what the traversal tests and the traversal benchmark check against the oracles.
"""

from __future__ import annotations

import numpy as np

from wgputrace.render.scene_records import SceneRecords
from wgputrace.testing.harness import frame_record, node_binding, run_kernel
from wgputrace.testing.oracles import as_vec4

KERNEL = """
//! include "{traversal}"
fn compute(i: u32) -> vec2<f32> {{
    let hit = closest_hit(Ray(inputs_0[i].xyz, inputs_1[i].xyz), FLOAT_MAX, NO_TRIANGLE);
    return vec2<f32>(hit.t, bitcast<f32>(hit.triangle));
}}
"""


def closest_hit(
    context, records: SceneRecords, origins: np.ndarray, directions: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(t, triangle) per ray from the shipped closest_hit of the traversal `records` were built for."""
    kind = records.acceleration.kind
    scene = {"triangles": records.triangles, "nodes": node_binding(context, records)}
    if kind == "flat":  # only the flat list reads the node count from the frame
        scene["frame"] = frame_record(len(records.nodes))
    out = run_kernel(
        context,
        KERNEL.format(traversal=f"geometry/traverse_{kind}.wgsl"),
        [as_vec4(origins), as_vec4(directions)],
        np.dtype((np.float32, 2)),
        len(origins),
        input_types=["vec4<f32>", "vec4<f32>"],
        output_type="vec2<f32>",
        scene=scene,
    )
    assert not np.isnan(out[:, 0]).any(), "closest_hit returned a NaN distance"
    return out[:, 0].astype(np.float64), out[:, 1].view(np.uint32)
