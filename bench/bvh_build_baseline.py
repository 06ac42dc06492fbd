"""The BVH builder against the builder of an earlier git revision, in one run: build time, SAH
cost, and the render time per sample of their trees.

    python -m bench.bvh_build_baseline
    python -m bench.bvh_build_baseline --cells 224 --repeats 3 --baseline 82b407f

The baseline is `wgputrace.bvh.binned_sah` as it was at `--baseline` (default 82b407f, the last
revision before the per-triangle records), loaded from git. Both build every scene (the
1,002,528-triangle `height_field`, a random soup, the Cornell box) interleaved, `repeats` times
each, after validating each tree (`bvh_failures`). Then both trees of the Cornell box and of a
100,000-triangle `sheet_scene` are rendered alike; the pictures must agree, and a few samples per
pixel of each are timed, interleaved: the render time per sample is what a tree's quality buys.
Writes bench/results/bvh_build_baseline_<adapter>.json.
"""

from __future__ import annotations

import importlib.util
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from functools import partial

import numpy as np

from bench.command_line import argument_parser, log, parse
from bench.provenance import Run, git
from bench.result_files import write_result
from bench.scenes import BIG_MESH_CELLS, height_field, sheet_scene
from bench.validation import bvh_failures
from wgputrace import Renderer, default_scene
from wgputrace.bvh import BVH, build_bvh
from wgputrace.render import scene_records

BASELINE_REVISION = "82b407f"
CURRENT = "current"
SOUP_TRIANGLES = 300_000
SOUP_SEED = 20240611
SIZE = 128
SPP = 4
MAX_DEPTH = 9
# Trees that make the same closest hits give the same picture up to exact ties of two hit
# distances, which each tree's order decides: a few pixels at most may differ.
MAX_DIFFERING_PIXEL_FRACTION = 0.01


def soup(count: int) -> np.ndarray:
    """Small random triangles in [-1, 1]^3."""
    rng = np.random.default_rng(SOUP_SEED)
    centres = rng.uniform(-1.0, 1.0, size=(count, 1, 3))
    return (centres + rng.normal(scale=0.01, size=(count, 3, 3))).astype(np.float32)


def baseline_builder(revision: str) -> Callable[..., BVH]:
    """build_bvh as `wgputrace.bvh.binned_sah` defined it at `revision`."""
    try:
        source = git("show", f"{revision}:wgputrace/bvh/binned_sah.py")
    except subprocess.CalledProcessError as error:
        raise SystemExit(f"cannot read the builder at revision {revision}: {error.stderr.strip()}") from None
    spec = importlib.util.spec_from_loader(f"binned_sah_{revision}", loader=None)
    module = importlib.util.module_from_spec(spec)
    exec(compile(source, f"{revision}:wgputrace/bvh/binned_sah.py", "exec"), module.__dict__)
    return module.build_bvh


def time_builds(vertices: np.ndarray, builders: dict[str, Callable[..., BVH]], repeats: int) -> dict:
    trees = {name: build(vertices) for name, build in builders.items()}
    for name, tree in trees.items():
        failures = bvh_failures(tree, vertices)
        if failures:
            raise SystemExit(f"variant {name!r}: the BVH is not valid, nothing timed: {failures}")
    seconds = {name: [] for name in builders}
    for _ in range(repeats):
        for name, build in builders.items():
            started = time.perf_counter()
            build(vertices)
            seconds[name].append(time.perf_counter() - started)
    reference = next(iter(builders))
    reference_seconds = statistics.median(seconds[reference])
    reference_cost = trees[reference].sah_cost()
    return {
        name: {
            "median_seconds": statistics.median(seconds[name]),
            "run_seconds": seconds[name],
            "seconds_over_reference": statistics.median(seconds[name]) / reference_seconds,
            "sah_cost": trees[name].sah_cost(),
            "sah_over_reference": trees[name].sah_cost() / reference_cost,
            "node_count": trees[name].node_count,
            "depth": trees[name].depth,
        }
        for name in builders
    }


def time_renders(scene_factory: Callable, builders: dict[str, Callable[..., BVH]], repeats: int) -> dict:
    """Seconds per sample per pixel at SIZE x SIZE with each builder's tree, interleaved."""
    original = scene_records.build_bvh
    renderers = {}
    try:
        for name, build in builders.items():
            # the renderer builds its tree through scene_records.build_bvh: swapped for the variant's
            scene_records.build_bvh = build
            renderers[name] = Renderer(scene_factory(), SIZE, SIZE, seed=1, max_depth=MAX_DEPTH)
    finally:
        scene_records.build_bvh = original
    images = {}
    for name, renderer in renderers.items():
        renderer.render(SPP)  # compiles, and the picture to validate
        images[name] = renderer.image()
    first = next(iter(images))
    for name, image in images.items():
        differing = np.mean(np.any(image != images[first], axis=-1))
        if not np.all(np.isfinite(image)) or differing > MAX_DIFFERING_PIXEL_FRACTION:
            raise SystemExit(f"tree {name!r}: picture not finite or {differing:.1%} of pixels differ from {first}")
    seconds = {name: [] for name in renderers}
    for _ in range(repeats):
        for name, renderer in renderers.items():
            renderer.reset()
            seconds[name].append(renderer.render(SPP).render_seconds / SPP)
    return {
        name: {
            "seconds_per_spp": statistics.median(seconds[name]),
            "run_seconds_per_spp": seconds[name],
            "sah_cost": renderer.records.acceleration.sah_cost(),
            "over_reference": statistics.median(seconds[name]) / statistics.median(seconds[first]),
        }
        for name, renderer in renderers.items()
    }


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, repeats=3)
    parser.add_argument(
        "--cells",
        type=int,
        default=BIG_MESH_CELLS,
        help=f"height field of 2 cells^2 triangles (default {BIG_MESH_CELLS})",
    )
    parser.add_argument("--baseline", default=BASELINE_REVISION, help="git revision of the builder to compare with")
    args = parse(parser, argv, "cells")
    run = Run()
    # the baseline first: ratios are to it
    builders = {f"baseline {args.baseline}": baseline_builder(args.baseline), CURRENT: build_bvh}
    vertices, faces = height_field(args.cells)
    scenes = {
        f"height field, {len(faces):,} triangles": vertices[faces],
        f"random soup, {SOUP_TRIANGLES:,} triangles": soup(SOUP_TRIANGLES),
        "Cornell box": default_scene().arrays().vertices,
    }
    builds = {}
    for scene, triangles in scenes.items():
        builds[scene] = time_builds(triangles, builders, args.repeats)
        log(scene)
        for name, row in builds[scene].items():
            log(
                f"  {name:22s} {row['median_seconds']:7.3f} s  x{row['seconds_over_reference']:.3f}  "
                f"SAH {row['sah_cost']:.4f} (x{row['sah_over_reference']:.4f})  {row['node_count']:,} nodes"
            )
    renders = {}
    for scene, factory in {
        "Cornell box": default_scene,
        "height field, 100,000 triangles": partial(sheet_scene, 100_000),
    }.items():
        renders[scene] = time_renders(factory, builders, args.repeats)
        log(f"{scene}, {SIZE}x{SIZE}, render time per sample per pixel")
        for name, row in renders[scene].items():
            log(
                f"  {name:22s} {row['seconds_per_spp'] * 1e3:7.1f} ms  x{row['over_reference']:.3f}  SAH {row['sah_cost']:.4f}"
            )
    result = {
        "scene": list(scenes),
        "width": SIZE,
        "height": SIZE,
        "spp": SPP,
        "max_depth": MAX_DEPTH,
        "repeats": args.repeats,
        "baseline_revision": args.baseline,
        "builds": builds,
        "renders": renders,
    }
    write_result("bvh_build_baseline", result, out=args.out, run=run)
    return 0


if __name__ == "__main__":
    sys.exit(main())
