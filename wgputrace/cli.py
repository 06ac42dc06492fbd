"""Command line: `wgputrace render` (headless, to PNG/EXR/NPY), `wgputrace info` and `wgputrace view`
(the window). The benchmarks live in the source checkout, not in the package: `python -m bench`."""

from __future__ import annotations

import argparse
import json
import sys
import time

from .cli_arguments import add_scene_arguments, add_view_arguments
from .image_io import FORMATS, save_image
from .loaders import load_scene


def argument_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="wgputrace",
        description="Monte Carlo path tracer on WGSL compute shaders.",
        epilog="The benchmarks run from a source checkout: python -m bench",
    )
    commands = parser.add_subparsers(dest="command", required=True)

    render = commands.add_parser("render", help="render a scene headless to .png, .exr or .npy")
    add_scene_arguments(render, size=(512, 512))
    render.add_argument("--spp", type=int, default=64, help="samples per pixel (default 64)")
    render.add_argument("--accel", choices=("bvh", "flat"), default="bvh", help="BVH, or trac0r's flat box list")
    render.add_argument(
        "--integrator",
        choices=("bsdf", "nee", "mis"),
        default="mis",
        help="direct light by BSDF sampling, light sampling, or both with MIS (default)",
    )
    render.add_argument("-o", "--output", default="render.png", help=f"output file ({', '.join(FORMATS)})")

    commands.add_parser("info", help="print the adapter, backend and the limits that matter")
    add_view_arguments(commands.add_parser("view", help="open the interactive viewer (a window; see README)"))
    return parser


def _render(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from .gpu.device import gpu
    from .render import Renderer

    load_start = time.perf_counter()
    scene = load_scene(args.scene)
    load_seconds = time.perf_counter() - load_start
    width, height = args.size
    context = gpu()
    start = time.perf_counter()
    renderer = Renderer(
        scene, width, height, seed=args.seed, max_depth=args.max_depth, accel=args.accel, integrator=args.integrator
    )
    setup_seconds = time.perf_counter() - start
    with tqdm(total=args.spp, unit="spp", desc="rendering", file=sys.stderr, dynamic_ncols=True) as bar:

        def progress(samples: int) -> None:
            bar.update(samples)
            bar.set_postfix_str(f"{renderer.stats.samples_per_second * width * height / 1e6:.2f} M samples/s")

        stats = renderer.render(args.spp, progress)
    path = save_image(args.output, renderer.image(), exposure=args.exposure)
    acceleration = renderer.records.acceleration
    print(f"adapter          {context.adapter_name}")
    print(
        f"scene            {args.scene}: {renderer.triangle_count:,} triangles, {len(renderer.records.materials)} materials, "
        f"loaded in {load_seconds:.2f} s"
    )
    print(
        f"gpu memory       {renderer.gpu_bytes_per_triangle:.1f} B per triangle (triangles, BVH nodes, materials, "
        f"lights; as allocated, spare capacity included)"
    )
    print(
        f"acceleration     {args.accel}: {acceleration.node_count:,} nodes, depth {acceleration.depth}, "
        f"SAH cost {acceleration.sah_cost():.2f}, built in {acceleration.build_seconds * 1e3:.1f} ms"
    )
    print(f"setup            {setup_seconds:.2f} s (BVH, buffers, pipeline)")
    print(
        f"render           {stats.samples_per_pixel} spp at {width}x{height} in {stats.render_seconds:.2f} s, "
        f"{stats.samples_per_second * width * height / 1e6:.3f} M samples/s"
    )
    if renderer.nonfinite_samples:
        print(f"non-finite       {renderer.nonfinite_samples} samples were NaN or infinite and counted as zero")
    if renderer.cut_short_samples:
        print(
            f"cut short        {renderer.cut_short_samples} samples ran out of the driver's loop budget "
            "and were counted as zero"
        )
    print(f"wrote            {path}")
    return 0


def _info() -> int:
    from .gpu.device import describe

    print(json.dumps(describe(), indent=2))
    return 0


def main(argv: list[str] | None = None) -> int:
    args = argument_parser().parse_args(argv)
    try:
        if args.command == "view":
            from .app import run  # the viewer's window and GPU code load only when it runs

            return run(args)
        return _render(args) if args.command == "render" else _info()
    except (ValueError, RuntimeError) as error:
        print(f"wgputrace: error: {error}", file=sys.stderr)
        return 2
