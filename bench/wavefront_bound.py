"""Whether a wavefront path tracer could beat the megakernel here: what it must pay per path and
bounce at least, against the most its compacted queues could save.

    python -m bench.wavefront_bound
    python -m bench.wavefront_bound --size 256x256 --spp 16

A wavefront (generate, extend, shade and shadow kernels joined by queues of path indices) keeps
every lane of a kernel busy, where the megakernel's lanes idle once their path has ended; with path
regeneration that idleness is what the path loop's lane utilisation leaves (`count_lanes`), so
compaction can make the megakernel at most 1 / utilisation as fast. Its cost is the path state
(`STATE_TEXELS` vec4s: ray, throughput, radiance, the MIS terms, the sampler's state, the pixel)
read and written between kernels, the hit record passed on and a compacted queue append, measured
here by two minimal kernels over SIZE paths (`state_round_trip`), against the megakernel's process
CPU time per path vertex on the Cornell box. Writes bench/results/wavefront_bound_<adapter>.json.
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np
import wgpu

from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from bench.timing import fresh_image
from wgputrace import Renderer, default_scene
from wgputrace.gpu.device import GpuContext
from wgputrace.render.ray_count import count_lanes, count_rays

MAX_DEPTH = 9
# The path state a wavefront keeps in memory between kernels, in vec4s: ray origin and direction,
# throughput, radiance, the previous vertex's MIS terms and position, eta scale and depth, the
# Sobol sampler's seed, index and draw and the alpha stream (4 words), the pixel.
STATE_TEXELS = 7
WORKGROUP = 64
# The two kernels: extend reads the state and writes a hit; shade reads both, writes the state back
# and appends the path to the next queue when it goes on (half of them here).
ROUND_TRIP = f"""
struct State {{ {", ".join(f"s{k}: vec4<u32>" for k in range(STATE_TEXELS))} }}
@group(0) @binding(0) var<storage, read_write> states: array<State>;
@group(0) @binding(1) var<storage, read_write> hits: array<vec2<u32>>;
@group(0) @binding(2) var<storage, read> queue_in: array<u32>;
@group(0) @binding(3) var<storage, read_write> queue_out: array<atomic<u32>>;
@compute @workgroup_size({WORKGROUP})
fn extend(@builtin(global_invocation_id) id: vec3<u32>) {{
    let path = queue_in[id.x];
    let state = states[path];
    hits[path] = vec2<u32>(state.s0.x + state.s1.y, state.s{STATE_TEXELS - 1}.x);
}}
@compute @workgroup_size({WORKGROUP})
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {{
    let path = queue_in[id.x];
    var state = states[path];
    let hit = hits[path];
    state.s0 += vec4<u32>(hit.x);
    state.s{STATE_TEXELS - 1}.y += hit.y;
    states[path] = state;
    if (hit.y & 1u) == 0u {{
        let slot = atomicAdd(&queue_out[0], 1u);
        atomicStore(&queue_out[slot + 1u], path);
    }}
}}
"""


def state_round_trip(context: GpuContext, paths: int, repeats: int) -> float:
    """Process CPU seconds per path and bounce of the two kernels over `paths` paths in a shuffled
    queue, the best of `repeats` submits of 10 bounces."""
    device = context.device
    usage = wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_DST
    buffers = (
        device.create_buffer(size=paths * STATE_TEXELS * 16, usage=usage),
        device.create_buffer(size=paths * 8, usage=usage),
        device.create_buffer_with_data(data=np.random.default_rng(1).permutation(paths).astype(np.uint32), usage=usage),
        device.create_buffer(size=(paths + 1) * 4, usage=usage),
    )
    module = device.create_shader_module(code=ROUND_TRIP)
    kernels = {}
    for entry in ("extend", "shade"):
        pipeline = device.create_compute_pipeline(layout="auto", compute={"module": module, "entry_point": entry})
        used = buffers if entry == "shade" else buffers[:3]
        entries = [{"binding": k, "resource": {"buffer": b}} for k, b in enumerate(used)]
        kernels[entry] = (pipeline, device.create_bind_group(layout=pipeline.get_bind_group_layout(0), entries=entries))

    def bounces(count: int) -> None:
        encoder = device.create_command_encoder()
        for _ in range(count):
            for pipeline, group in kernels.values():
                compute = encoder.begin_compute_pass()
                compute.set_pipeline(pipeline)
                compute.set_bind_group(0, group)
                compute.dispatch_workgroups(paths // WORKGROUP)
                compute.end()
            encoder.clear_buffer(buffers[3], 0, 4)
        device.queue.submit([encoder.finish()])
        context.finish()

    bounces(1)  # compiles on lavapipe
    seconds = []
    for _ in range(repeats):
        start = time.process_time()
        bounces(10)
        seconds.append(time.process_time() - start)
    return min(seconds) / 10 / paths


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(256, 256), spp=16, repeats=5, seed=1)
    args = parse(parser, argv)
    width, height = args.size
    if width * height % WORKGROUP:
        parser.error(f"the image's pixels must be a multiple of {WORKGROUP}")
    run = Run()
    renderer = Renderer(default_scene(), width, height, seed=args.seed, max_depth=MAX_DEPTH)
    fresh_image(renderer, renderer.samples_per_dispatch)  # compiles on lavapipe
    cpu = [fresh_image(renderer, args.spp, from_seed=True)[3] for _ in range(args.repeats)]
    renderer.restart()
    rays = count_rays(renderer, args.spp)
    lanes = count_lanes(renderer, args.spp) if renderer.context.has_subgroups else None
    vertex_seconds = statistics.median(cpu) / rays.closest_hit
    traffic = state_round_trip(renderer.context, width * height, args.repeats)
    utilisation = lanes.utilisation("path") if lanes else None
    most_saved = None if utilisation is None else 1.0 / utilisation
    log(f"megakernel {vertex_seconds * 1e9:.0f} ns per vertex, wavefront state {traffic * 1e9:.0f} ns per bounce")
    result = {
        "scene": "cornell",
        "width": width,
        "height": height,
        "spp": args.spp,
        "max_depth": MAX_DEPTH,
        "samples_per_dispatch": renderer.samples_per_dispatch,
        "megakernel_process_cpu_seconds": cpu,
        "closest_hit_rays_per_path": rays.closest_hit / rays.camera,
        "megakernel_process_cpu_seconds_per_vertex": vertex_seconds,
        "path_loop_lane_utilisation": utilisation,
        "most_a_wavefront_could_save": most_saved,
        "state_texels": STATE_TEXELS,
        "wavefront_state_round_trip_seconds_per_bounce": traffic,
        "wavefront_overhead_over_megakernel_vertex": traffic / vertex_seconds,
        "note": "a wavefront gains at most `most_a_wavefront_could_save` on the megakernel's path loop and pays at "
        "least `wavefront_overhead_over_megakernel_vertex` of a megakernel vertex per bounce, before its "
        "shadow-ray and camera kernels, indirect dispatches and queue compaction",
    }
    write_result("wavefront_bound", result, out=args.out, run=run)
    print(
        f"megakernel ({renderer.samples_per_dispatch} samples per dispatch): {vertex_seconds * 1e9:.0f} ns of process "
        f"CPU per path vertex, path-loop lanes busy {utilisation if utilisation is None else f'{utilisation:.3f}'}; "
        f"a wavefront's state round trip alone: {traffic * 1e9:.0f} ns per path and bounce "
        f"({traffic / vertex_seconds:.0%} of a vertex) against at most "
        f"{'-' if most_saved is None else f'x{most_saved:.2f}'} from compaction"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
