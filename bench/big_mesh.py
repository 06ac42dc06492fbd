"""A 1,000,000-triangle mesh from file to picture: load, BVH build, GPU upload, render, and a refit.

    python -m bench.big_mesh
    python -m bench.big_mesh --cells 708 --size 256x256 --spp 1

The mesh is `height_field` with 2 x cells^2 triangles (708 cells: 1,002,528), written once as
binary PLY (through trimesh) and as OBJ (our own reader), lit by a lamp above it. Each file is
loaded and checked; the PLY scene's renderer setup is timed as BVH build and the rest, its image
validated before the render is timed, and last the mesh is moved and refit. Load times are medians
of `repeats`, the rest single runs. Writes bench/results/big_mesh_<adapter>.json.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from bench.scenes import BIG_MESH_CELLS, height_field
from bench.validation import image_failures
from wgputrace import Camera, Emitter, Renderer, load_scene, make_plane, model_matrix


def write_files(directory: Path, vertices: np.ndarray, faces: np.ndarray) -> dict[str, Path]:
    import trimesh

    ply = directory / "sheet.ply"
    ply.write_bytes(trimesh.Trimesh(vertices, faces, process=False).export(file_type="ply", encoding="binary"))
    obj = directory / "sheet.obj"
    with obj.open("w") as out:
        np.savetxt(out, vertices, fmt="v %.9g %.9g %.9g")
        np.savetxt(out, faces + 1, fmt="f %d %d %d")
    return {"ply": ply, "obj": obj}


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(256, 256), spp=1, repeats=3)
    parser.add_argument(
        "--cells",
        type=int,
        default=BIG_MESH_CELLS,
        help=f"a height field of 2 cells^2 triangles (default {BIG_MESH_CELLS})",
    )
    args = parse(parser, argv, "cells")
    run = Run()
    width, height = args.size
    vertices, faces = height_field(args.cells)
    result = {"triangles_in_file": len(faces), "loads": {}}
    scenes = {}
    with tempfile.TemporaryDirectory() as directory:
        files = write_files(Path(directory), vertices, faces)
        for kind, path in files.items():
            seconds = []
            for _ in range(args.repeats):
                start = time.perf_counter()
                scene = load_scene(path)
                seconds.append(time.perf_counter() - start)
            if scene.triangle_count != len(faces) or not np.all(np.isfinite(scene.shapes[0].world_vertices)):
                raise SystemExit(
                    f"{kind}: {scene.triangle_count} triangles loaded of {len(faces)}, or non-finite corners"
                )
            scenes[kind] = scene
            result["loads"][kind] = {"bytes": path.stat().st_size, "median_seconds": statistics.median(seconds)}
            log(f"load {kind}: {path.stat().st_size / 1e6:.1f} MB in {statistics.median(seconds):.2f} s")

    scene = scenes["ply"]
    lamp = make_plane((0, 1.5, 0), (np.pi, 0, 0), (0.6, 0.6), Emitter("lamp", emittance=12.0), "lamp")
    scene.add(lamp)
    scene.camera = Camera.looking_at((0.0, 1.4, -2.2), (0, 0, 0), vfov_degrees=45.0)
    start = time.perf_counter()
    renderer = Renderer(scene, width, height, seed=1)
    setup_seconds = time.perf_counter() - start
    build_seconds = renderer.records.acceleration.build_seconds
    renderer.render(1)  # validate (and compile) before timing
    failures = image_failures(renderer.image(), renderer.dropped_samples, (1e-3, np.inf))
    if failures:
        raise SystemExit(f"the image is not valid, nothing timed: {failures}")
    renderer.reset()
    render_stats = renderer.render(args.spp)
    start = time.perf_counter()
    scene.shapes[0].transform = model_matrix((0.0, 0.05, 0.0), (0, 0, 0), 1.0)
    uploads = renderer.update()
    refit_seconds = time.perf_counter() - start
    mirror = renderer._mirror
    result.update(
        {
            "scene": f"height field of {len(faces):,} triangles under a square lamp",
            "triangles_rendered": renderer.triangle_count,
            "bvh": {
                "build_seconds": build_seconds,
                "nodes": renderer.records.acceleration.node_count,
                "wide_records": len(renderer.records.nodes),  # what the GPU holds (`wgputrace.bvh.wide`)
                "depth": renderer.records.acceleration.depth,
                "sah_cost": mirror.refitter.built_cost,
            },
            "renderer_setup_seconds": setup_seconds,
            "setup_besides_bvh_seconds": setup_seconds - build_seconds,
            "gpu_bytes_per_triangle": renderer.gpu_bytes_per_triangle,
            "gpu_scene_bytes": renderer.gpu_scene_bytes,
            "width": width,
            "height": height,
            "spp": args.spp,
            "max_depth": renderer.max_depth,
            "render_seconds": render_stats.render_seconds,
            "move_mesh": {
                "update_seconds": refit_seconds,
                "refits": mirror.refits,
                "rebuilds": mirror.rebuilds,
                "degradation": mirror.refitter.degradation,
                "uploads": {name: vars(count) for name, count in uploads.items()},
            },
        }
    )
    print(
        f"renderer setup {setup_seconds:.2f} s (BVH build {build_seconds:.2f} s, {result['bvh']['nodes']:,} nodes, "
        f"{result['bvh']['wide_records']:,} 4-wide records), "
        f"{renderer.gpu_bytes_per_triangle:.1f} GPU bytes per triangle"
    )
    print(f"render {args.spp} spp at {width}x{height}: {render_stats.render_seconds:.2f} s")
    print(f"move the mesh: update {refit_seconds:.2f} s, uploads {result['move_mesh']['uploads']}")
    write_result("big_mesh", result, out=args.out, run=run)
    return 0


if __name__ == "__main__":
    sys.exit(main())
