"""A 1,000,000-triangle mesh from file to picture: load, BVH build, GPU upload, render, and a refit.

    python bench/big_mesh.py                  (or: python -m bench.big_mesh)
    python bench/big_mesh.py --cells 708 --size 256x256 --spp 1

The mesh is a wavy height field of 2 x cells^2 triangles (708 cells: 1,002,528 triangles), written
once as binary PLY (through trimesh) and as OBJ (our own reader), lit by a lamp above it. Each
file is loaded into a Scene and checked (triangle count, finite vertices); the PLY scene is then
rendered: the Renderer's setup is split into the BVH build and the rest (buffers, upload,
pipeline); the image is validated (finite, lit) before the render is timed; last, the mesh is
moved and the renderer refits (the timing of one update). Load times are the median of
`repeats`; the rest are single runs (seconds each). Writes bench/results/big_mesh_<adapter>.json.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.common import write_result  # noqa: E402
from wgputrace import Camera, Emitter, Renderer, load_scene, make_plane, model_matrix  # noqa: E402
from wgputrace.cli import parse_size  # noqa: E402

CELLS = 708  # 2 x 708^2 = 1,002,528 triangles


def height_field(cells: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertices ((cells + 1)^2, 3) and faces (2 cells^2, 3) of a wavy sheet over [-1, 1]^2, facing +y."""
    x, z = np.meshgrid(np.linspace(-1, 1, cells + 1), np.linspace(-1, 1, cells + 1), indexing="ij")
    y = 0.1 * np.sin(9 * x) * np.cos(7 * z)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    a = (i * (cells + 1) + j).ravel()
    b, c, d = a + 1, a + cells + 1, a + cells + 2
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    return vertices, faces


def write_files(directory: Path, vertices: np.ndarray, faces: np.ndarray) -> dict[str, Path]:
    import trimesh

    ply = directory / "sheet.ply"
    ply.write_bytes(trimesh.Trimesh(vertices, faces, process=False).export(file_type="ply", encoding="binary"))
    obj = directory / "sheet.obj"
    with obj.open("w") as out:
        np.savetxt(out, vertices, fmt="v %.9g %.9g %.9g")
        np.savetxt(out, faces + 1, fmt="f %d %d %d")
    return {"ply": ply, "obj": obj}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=CELLS)
    parser.add_argument("--size", type=parse_size, default=(256, 256))
    parser.add_argument("--spp", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    width, height = args.size
    vertices, faces = height_field(args.cells)
    result = {"benchmark": "big_mesh", "triangles_in_file": len(faces), "loads": {}}
    scenes = {}
    with tempfile.TemporaryDirectory() as directory:
        files = write_files(Path(directory), vertices, faces)
        for kind, path in files.items():
            seconds = []
            for _ in range(args.repeats):
                start = time.perf_counter()
                scene = load_scene(path)
                seconds.append(time.perf_counter() - start)
            assert scene.triangle_count == len(faces) and np.all(np.isfinite(scene.shapes[0].world_vertices))
            scenes[kind] = scene
            result["loads"][kind] = {"bytes": path.stat().st_size, "median_seconds": statistics.median(seconds)}
            print(f"load {kind}: {path.stat().st_size / 1e6:.1f} MB in {statistics.median(seconds):.2f} s")

    scene = scenes["ply"]
    lamp = make_plane((0, 1.5, 0), (np.pi, 0, 0), (0.6, 0.6), Emitter("lamp", emittance=12.0), "lamp")
    scene.add(lamp)
    scene.camera = Camera.looking_at((0.0, 1.4, -2.2), (0, 0, 0), vfov_degrees=45.0)
    start = time.perf_counter()
    renderer = Renderer(scene, width, height, seed=1)
    setup_seconds = time.perf_counter() - start
    build_seconds = renderer.records.acceleration.build_seconds
    renderer.render(1)  # validate (and compile) before timing
    image = renderer.image()
    if not (np.all(np.isfinite(image)) and image.mean() > 0):
        raise SystemExit(f"the image is not valid: finite {np.all(np.isfinite(image))}, mean {image.mean()}")
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
                "wide_records": len(renderer.records.nodes),  # what the GPU holds (bvh/wide.py)
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
    print(f"wrote {write_result('big_mesh', result)['json']}")


if __name__ == "__main__":
    main()
