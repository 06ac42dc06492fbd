"""Instancing at scale: 10,000 instances of a 100,000-triangle mesh (a billion triangles drawn) on
the GPU, its memory and time per sample beside the same instances flattened into unique triangles
where those fit.

    python -m bench.instancing
    python -m bench.instancing --instances 10 100 10000 --unique 10 100 --size 128x128 --spp 2

The mesh is a wavy torus (`torus_mesh`) stored once; a square grid of instances, each turned and
scaled, stands on a ground under a lamp (`instanced_field`), seen from above at an angle. Each
configuration is built (setup timed), validated on one sample (finite, no dropped samples, mean
radiance in a band) and then timed from the seed, medians of --repeats. Memory is the scene's GPU
buffers as allocated (`Renderer.gpu_scene_bytes`), beside the adapter's buffer limits. Flattened
runs stop at the first count that does not fit (memory or the adapter's limits), recorded as such.
Writes bench/results/instancing_<adapter>.json and .png.
"""

from __future__ import annotations

import math
import statistics
import sys
import time

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from bench.validation import image_failures
from wgputrace import Camera, Diffuse, Emitter, Renderer, Scene, Shape, make_plane, model_matrix
from wgputrace.gpu.device import DeviceLimitError

MESH_TRIANGLES = 100_000
SEED = 1
MAX_DEPTH = 4
SPACING = 3.0  # between instances of the grid; the torus is about 2.6 across at the largest scale
# The lit field averages about 0.1-0.3 here whatever the count: far below means the lamp or the
# instances are missed, far above exploding weights.
MEAN_RADIANCE_BAND = (0.01, 5.0)


def torus_mesh(triangles: int = MESH_TRIANGLES) -> Shape:
    """A torus (radii 1 and 0.3, wavy) of `triangles` triangles (rounded to 2 u v with u = 5/4 v)."""
    v_cells = max(3, round(math.sqrt(triangles / 2.5)))
    u_cells = max(3, round(triangles / (2 * v_cells)))
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, u_cells + 1), np.linspace(0, 2 * np.pi, v_cells + 1), indexing="ij")
    tube = 0.3 * (1.0 + 0.15 * np.sin(7 * u) * np.cos(5 * v))
    points = np.stack(
        [(1.0 + tube * np.cos(v)) * np.cos(u), tube * np.sin(v), (1.0 + tube * np.cos(v)) * np.sin(u)], -1
    )
    i, j = np.meshgrid(np.arange(u_cells), np.arange(v_cells), indexing="ij")
    a, b, c, d = points[i, j], points[i + 1, j], points[i, j + 1], points[i + 1, j + 1]
    corners = np.concatenate([np.stack([a, c, b], -2), np.stack([b, c, d], -2)], axis=0).reshape(-1, 3, 3)
    return Shape("torus", corners, Diffuse("torus", (0.7, 0.5, 0.3)))


def instanced_field(mesh: Shape, instances: int) -> Scene:
    """`instances` placements of `mesh` on a square grid over a ground, under a lamp, each turned and
    scaled by a seeded generator, seen from above at an angle."""
    side = math.ceil(math.sqrt(instances))
    extent = side * SPACING
    ground = make_plane((0, -0.5, 0), (0, 0, 0), (extent + 4, extent + 4), Diffuse("ground", (0.5, 0.5, 0.5)), "ground")
    lamp = make_plane(
        (0, extent, 0), (np.pi, 0, 0), (extent, extent), Emitter("lamp", (1, 1, 1), emittance=3.0), "lamp"
    )
    camera = Camera.looking_at((0.0, 0.45 * extent + 3, -0.6 * extent - 3), (0, 0, 0), vfov_degrees=60.0)
    scene = Scene([ground, lamp], camera)
    rng = np.random.default_rng(SEED)
    cells = np.stack(np.divmod(np.arange(instances), side), axis=1)
    for index, (row, column) in enumerate(cells):
        position = ((row - (side - 1) / 2) * SPACING, 0.0, (column - (side - 1) / 2) * SPACING)
        turn = (rng.uniform(-0.4, 0.4), rng.uniform(0, 2 * np.pi), 0.0)
        scene.add_instance(mesh, model_matrix(position, turn, rng.uniform(0.8, 1.2)), f"torus{index}")
    return scene


def measure(scene: Scene, width: int, height: int, spp: int, repeats: int) -> dict:
    """Setup, memory and time per sample of one scene, its image validated before timing."""
    start = time.perf_counter()
    renderer = Renderer(scene, width, height, seed=SEED, max_depth=MAX_DEPTH)
    setup_seconds = time.perf_counter() - start
    renderer.render(1)  # validate (and compile) before timing
    image = renderer.image()
    failures = image_failures(image, renderer.dropped_samples, MEAN_RADIANCE_BAND)
    if failures:
        raise SystemExit(f"the image is not valid, nothing timed: {failures}")
    seconds = []
    for _ in range(repeats):
        renderer.reset()
        seconds.append(renderer.render(spp).render_seconds / spp)
    scene_bytes = renderer.gpu_scene_bytes
    return {
        "triangles_stored": renderer.triangle_count,
        "setup_seconds": setup_seconds,
        "gpu_scene_bytes": int(sum(scene_bytes.values())),
        "gpu_scene_bytes_by_array": scene_bytes,
        "largest_array_bytes": int(max(scene_bytes.values())),
        "seconds_per_sample": statistics.median(seconds),
        "seconds_per_sample_runs": seconds,
        "mean_radiance": float(image.mean()),
    }


def plot(path, result: dict) -> None:
    chart = figure(9.0, 3.6)
    memory, timing = chart.add_subplot(1, 2, 1), chart.add_subplot(1, 2, 2)
    for kind, marker in (("instanced", "o-"), ("unique", "s--")):
        runs = [run for run in result["runs"] if run["kind"] == kind and "seconds_per_sample" in run]
        drawn = [run["triangles_drawn"] for run in runs]
        memory.plot(drawn, [run["gpu_scene_bytes"] / 2**20 for run in runs], marker, label=kind)
        timing.plot(drawn, [run["seconds_per_sample"] for run in runs], marker, label=kind)
    for axes, label in ((memory, "GPU scene MiB"), (timing, "seconds per sample")):
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_xlabel("triangles drawn")
        axes.set_ylabel(label)
        axes.legend()
        axes.grid(True, which="both", alpha=0.3)
    title = f"{result['mesh_triangles']:,}-triangle mesh, instanced or flattened, {result['width']}x{result['height']}"
    save_figure(chart, path, result, title)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(128, 128), spp=2, repeats=3)
    parser.add_argument("--instances", type=int, nargs="+", default=[10, 100, 10_000], help="instance counts drawn")
    parser.add_argument("--unique", type=int, nargs="+", default=[10, 100], help="instance counts flattened")
    parser.add_argument("--mesh-triangles", type=int, default=MESH_TRIANGLES, help="triangles of the mesh")
    args = parse(parser, argv, "instances", "unique", "mesh_triangles")
    run = Run()
    width, height = args.size
    mesh = torus_mesh(args.mesh_triangles)
    runs = []
    for kind, counts in (("instanced", args.instances), ("unique", args.unique)):
        for count in counts:
            scene = instanced_field(mesh, count)
            drawn = count * mesh.triangle_count
            entry = {"kind": kind, "instances": count, "triangles_drawn": drawn}
            try:
                measured = measure(
                    scene if kind == "instanced" else scene.flattened(), width, height, args.spp, args.repeats
                )
            except (DeviceLimitError, MemoryError) as error:
                entry["does_not_fit"] = " ".join(str(error).split())
                runs.append(entry)
                log(f"{kind} {count:,} instances ({drawn:,} triangles): does not fit: {entry['does_not_fit']}")
                break
            entry.update({**measured, "triangles_drawn": drawn})
            runs.append(entry)
            log(
                f"{kind} {count:,} instances ({drawn:,} triangles): {entry['gpu_scene_bytes'] / 2**20:.1f} MiB on the GPU, "
                f"{entry['seconds_per_sample']:.3f} s per sample, setup {entry['setup_seconds']:.1f} s"
            )
    result = {
        "scene": f"instanced_field: a grid of instances of a {mesh.triangle_count:,}-triangle torus under a lamp",
        "mesh_triangles": mesh.triangle_count,
        "width": width,
        "height": height,
        "spp": args.spp,
        "max_depth": MAX_DEPTH,
        "runs": runs,
    }
    write_result("instancing", result, out=args.out, run=run, plot=plot)
    return 0


if __name__ == "__main__":
    sys.exit(main())
