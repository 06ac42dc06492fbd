"""BVH build time and SAH cost against triangle count, through the builder's public API.

    python -m bench.bvh_build
    python -m bench.bvh_build --triangles 1000 100000 --repeats 3

The triangles are `sheet_scene`'s, the sheet `bench.scaling` renders, built by
`wgputrace.bvh.build_bvh` with its default parameters. Each count: one build validated
(`bvh_failures`), then `repeats` timed builds with every CPU and as many with one worker,
alternating so that both see the same load; medians. SAH cost is `BVH.sah_cost()`. The build runs
in numpy on the CPU, but results are filed by adapter like every benchmark's. Target (issue 8):
1,000,000 triangles built in under 2 s on the 2-core development machine. Writes
bench/results/bvh_build_<adapter>.json and .png.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from bench.scenes import TRIANGLE_COUNTS, sheet_scene
from bench.validation import bvh_failures
from wgputrace.bvh import build_bvh
from wgputrace.bvh.forked_subtrees import available_workers

TARGET_TRIANGLES = 1_000_000
TARGET_SECONDS = 2.0


def measure(triangles: int, repeats: int) -> dict:
    vertices = np.ascontiguousarray(sheet_scene(triangles).shapes[0].world_vertices, dtype=np.float32)
    bvh = build_bvh(vertices)
    failures = bvh_failures(bvh, vertices)
    if failures:
        raise SystemExit(f"{len(vertices)} triangles: the BVH is not valid, nothing timed: {failures}")
    seconds = {None: [], 1: []}  # by worker count: the default (every CPU) and one
    for _ in range(repeats):
        for workers, times in seconds.items():
            started = time.perf_counter()
            build_bvh(vertices, workers=workers)
            times.append(time.perf_counter() - started)
    return {
        "triangles_requested": triangles,  # the sheet's cells are square: the count comes out near it
        "triangles": len(vertices),
        "median_seconds": statistics.median(seconds[None]),
        "run_seconds": seconds[None],
        "one_worker_median_seconds": statistics.median(seconds[1]),
        "one_worker_run_seconds": seconds[1],
        "sah_cost": bvh.sah_cost(),
        "node_count": bvh.node_count,
        "depth": bvh.depth,
    }


def plot(path: Path, result: dict) -> None:
    chart = figure(11.0, 4.4)
    timing, cost = chart.subplots(1, 2)
    x = [p["triangles"] for p in result["points"]]
    timing.loglog(x, [p["median_seconds"] for p in result["points"]], "o-", label=f"{result['workers']} workers")
    timing.loglog(x, [p["one_worker_median_seconds"] for p in result["points"]], "s--", label="1 worker")
    target = result["target"]
    timing.axhline(target["seconds"], color="grey", linestyle=":", label=f"target {target['seconds']:g} s")
    timing.set_ylabel(f"seconds (median of {result['repeats']})")
    timing.legend()
    if target["measured_seconds"] is not None:
        timing.set_title(f"{target['triangles']:,} triangles: {target['measured_seconds']:.2f} s", fontsize=9)
    cost.semilogx(x, [p["sah_cost"] for p in result["points"]], "o-")
    cost.set_ylabel("SAH cost (C_t = C_i = 1)")
    cost.set_ylim(0, None)
    for axes in (timing, cost):
        axes.set_xlabel("triangles")
        axes.grid(which="both", alpha=0.3)
    save_figure(chart, path, result, f"wgputrace BVH build (binned SAH, numpy), {result['scene']}")


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, repeats=3)
    parser.add_argument("--triangles", type=int, nargs="+", default=list(TRIANGLE_COUNTS), help="triangle counts")
    args = parse(parser, argv, "triangles")
    run = Run()
    points = []
    for triangles in sorted(set(args.triangles)):
        p = measure(triangles, args.repeats)
        points.append(p)
        log(
            f"{p['triangles']:>9,} triangles: {p['median_seconds']:.3f} s ({p['one_worker_median_seconds']:.3f} s "
            f"with 1 worker), SAH cost {p['sah_cost']:.1f}"
        )
    at_target = [p for p in points if p["triangles_requested"] == TARGET_TRIANGLES]
    measured = at_target[0]["median_seconds"] if at_target else None
    result = {
        "scene": "bench/scaling.py's height field and lamp",
        **dict.fromkeys(("width", "height", "spp", "max_depth")),  # a build renders nothing
        "repeats": args.repeats,
        "builder": "wgputrace.bvh.build_bvh, default parameters; also workers=1, alternating",
        "workers": available_workers(),
        "points": points,
        "target": {
            "triangles": at_target[0]["triangles"] if at_target else TARGET_TRIANGLES,
            "seconds": TARGET_SECONDS,
            "measured_seconds": measured,
            "met": None if measured is None else measured < TARGET_SECONDS,
        },
    }
    write_result("bvh_build", result, out=args.out, plot=plot, run=run)
    return 0


if __name__ == "__main__":
    sys.exit(main())
