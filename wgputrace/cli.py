"""Command line: `wgputrace render` (headless, to PNG/EXR/NPY), `wgputrace info`, `wgputrace view` (the window)
and `wgputrace bench` (the benchmark suite, from a source checkout)."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from .image_io import FORMATS, save_image
from .loaders import FORMATS as SCENE_FORMATS
from .loaders import load_scene
from .scene import Scene
from .scenes import BUILTIN_SCENES, DEFAULT_SCENE, scene_by_name


def parse_size(text: str) -> tuple[int, int]:
    """argparse type for WIDTHxHEIGHT (also used by the benchmarks)."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 512x512, got {text!r}") from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"size must be positive, got {text!r}")
    return width, height


def scene_from_argument(text: str) -> Scene:
    """SCENE on the command line: an existing file is loaded, anything else names a built-in scene."""
    return load_scene(text) if Path(text).is_file() else scene_by_name(text)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="wgputrace", description="Monte Carlo path tracer on WGSL compute shaders.")
    commands = parser.add_subparsers(dest="command", required=True)

    render = commands.add_parser("render", help="render a scene headless to .png, .exr or .npy")
    render.add_argument(
        "scene",
        nargs="?",
        default=DEFAULT_SCENE,
        help=f"a scene file ({' '.join(SCENE_FORMATS)}) or a built-in scene: {', '.join(BUILTIN_SCENES)}",
    )
    render.add_argument("--spp", type=int, default=64, help="samples per pixel (default 64)")
    render.add_argument("--size", type=parse_size, default=(512, 512), help="WIDTHxHEIGHT (default 512x512)")
    render.add_argument("--max-depth", type=int, default=9, help="path vertices, Mitsuba's meaning; -1 = no limit")
    render.add_argument("--seed", type=int, default=1, help="random seed: same seed and adapter, same image")
    render.add_argument("--accel", choices=("bvh", "flat"), default="bvh", help="BVH, or trac0r's flat box list")
    render.add_argument(
        "--integrator",
        choices=("bsdf", "nee", "mis"),
        default="mis",
        help="direct light by BSDF sampling, light sampling, or both with MIS (default)",
    )
    render.add_argument("--exposure", type=float, default=1.0, help="multiplies radiance before PNG tone mapping")
    render.add_argument("-o", "--output", default="render.png", help=f"output file ({', '.join(FORMATS)})")

    commands.add_parser("info", help="print the adapter, backend and the limits that matter")

    from .app import add_arguments  # the viewer's arguments; its window code loads only when it runs

    add_arguments(commands.add_parser("view", help="open the interactive viewer (a window; see README)"))
    # listed for --help only: main() hands everything after "bench" to the suite's own parser
    commands.add_parser("bench", help="run the benchmark suite, `python -m bench` (from a source checkout)")
    return parser


def _render(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from .gpu.device import gpu
    from .render import Renderer

    load_start = time.perf_counter()
    scene = scene_from_argument(args.scene)
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


def _bench(arguments: list[str]) -> int:
    """`python -m bench ARGUMENTS` in a source checkout: the working directory's, else the one this
    package was imported from (an editable install)."""
    candidates = (Path.cwd(), Path(__file__).resolve().parent.parent)
    checkout = next((path for path in candidates if (path / "bench" / "__main__.py").is_file()), None)
    if checkout is None:
        print(
            "wgputrace: error: the benchmarks live in the source checkout, not in the wheel, and neither the "
            f"working directory nor {candidates[1]} holds bench/__main__.py: run `wgputrace bench` (or "
            "`python -m bench`) in a clone of the repository",
            file=sys.stderr,
        )
        return 2
    sys.path.insert(0, str(checkout))
    from bench.__main__ import main as bench_main

    return bench_main(arguments)


def _info() -> int:
    from .gpu.device import describe

    print(json.dumps(describe(), indent=2))
    return 0


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["bench"]:
        return _bench(argv[1:])
    args = _parser().parse_args(argv)
    try:
        if args.command == "view":
            from .app import run

            return run(args)
        return _render(args) if args.command == "render" else _info()
    except (ValueError, RuntimeError) as error:
        print(f"wgputrace: error: {error}", file=sys.stderr)
        return 2
