"""BVH build time and SAH cost against triangle count, through the builder's public API.

    python bench/bvh_build.py                     (or: python -m bench.bvh_build)
    python bench/bvh_build.py --triangles 1000 100000 --repeats 3

The triangles are bench/scaling.py's height field (the same sheet that is rendered there), built
by `wgputrace.bvh.build_bvh` with its default parameters. Each count: one build validated first
(triangle_order a permutation, leaves covering every triangle exactly once, the root box equal to
the mesh's bounds), then `repeats` timed builds with the default worker count (every CPU) and as
many with one worker, alternating; the medians count. SAH cost is the tree's own
`BVH.sah_cost()` (traversal and intersection cost 1). The build runs on the CPU in numpy, so it
does not depend on the adapter, but results are filed by adapter like every benchmark's.

Target (issue 8): 1,000,000 triangles built in under 2 s on the 2-core development machine.
Writes bench/results/bvh_build_<adapter>.json and .png.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.common import RESULTS_DIR, load_average, write_result  # noqa: E402
from bench.scaling import TRIANGLE_COUNTS, sheet_scene  # noqa: E402
from wgputrace.bvh import BVH, build_bvh  # noqa: E402
from wgputrace.bvh.forked_subtrees import available_workers  # noqa: E402

TARGET_TRIANGLES = 1_000_000
TARGET_SECONDS = 2.0


def validation_failures(bvh: BVH, vertices: np.ndarray) -> list[str]:
    failures = []
    count = len(vertices)
    if not np.array_equal(np.sort(bvh.triangle_order), np.arange(count)):
        failures.append("triangle_order is not a permutation of the triangles")
    leaves = bvh.triangle_count > 0
    first, size = bvh.left_or_first[leaves].astype(np.int64), bvh.triangle_count[leaves].astype(np.int64)
    # every slot of every leaf's range [first, first + size), as one flat array
    slots = np.repeat(first - (np.cumsum(size) - size), size) + np.arange(size.sum())
    covered = np.bincount(slots, minlength=count)
    if not np.all(covered == 1):
        failures.append(f"{np.count_nonzero(covered != 1)} triangle slots are not in exactly one leaf")
    corners = vertices.reshape(-1, 3)
    if not (
        np.array_equal(bvh.bounds_min[0], corners.min(axis=0))
        and np.array_equal(bvh.bounds_max[0], corners.max(axis=0))
    ):
        failures.append(f"root box {bvh.bounds_min[0]} .. {bvh.bounds_max[0]} is not the mesh's bounds")
    return failures


def measure(triangles: int, repeats: int) -> dict:
    vertices = np.ascontiguousarray(sheet_scene(triangles).shapes[0].world_vertices, dtype=np.float32)
    bvh = build_bvh(vertices)
    failures = validation_failures(bvh, vertices)
    if failures:
        raise SystemExit(f"{len(vertices)} triangles: the BVH is not valid, nothing timed: {failures}")
    # The default (every CPU) and one worker alternate, so both see the same load.
    seconds, one_worker_seconds = [], []
    for _ in range(repeats):
        for workers, times in ((None, seconds), (1, one_worker_seconds)):
            started = time.perf_counter()
            build_bvh(vertices, workers=workers)
            times.append(time.perf_counter() - started)
    return {
        "triangles_requested": triangles,  # the sheet's cells are square: the count comes out near it
        "triangles": len(vertices),
        "median_seconds": statistics.median(seconds),
        "run_seconds": seconds,
        "one_worker_median_seconds": statistics.median(one_worker_seconds),
        "one_worker_run_seconds": one_worker_seconds,
        "sah_cost": bvh.sah_cost(),
        "node_count": bvh.node_count,
        "depth": bvh.depth,
    }


def plot(path: Path, result: dict) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11.0, 4.4))
    FigureCanvasAgg(figure)
    timing, cost = figure.subplots(1, 2)
    x = [p["triangles"] for p in result["points"]]
    timing.loglog(x, [p["median_seconds"] for p in result["points"]], "o-", label=f"{result['workers']} workers")
    timing.loglog(x, [p["one_worker_median_seconds"] for p in result["points"]], "s--", label="1 worker")
    timing.axhline(result["target"]["seconds"], color="grey", linestyle=":", label=f"target {TARGET_SECONDS:g} s")
    timing.set_xlabel("triangles")
    timing.set_ylabel(f"seconds (median of {result['repeats']})")
    timing.grid(which="both", alpha=0.3)
    timing.legend()
    target = result["target"]
    if target["measured_seconds"] is not None:
        timing.set_title(f"{target['triangles']:,} triangles: {target['measured_seconds']:.2f} s", fontsize=9)
    cost.semilogx(x, [p["sah_cost"] for p in result["points"]], "o-")
    cost.set_xlabel("triangles")
    cost.set_ylabel("SAH cost (C_t = C_i = 1)")
    cost.set_ylim(0, None)
    cost.grid(which="both", alpha=0.3)
    figure.suptitle(
        f"wgputrace BVH build (binned SAH, numpy), {result['scene']}; rev {result['git_revision']}, "
        f"{result['environment']['cpu_count']} cores, load {result['load_average_before_after'][0]}",
        fontsize=9,
    )
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, nargs="+", default=list(TRIANGLE_COUNTS), help="triangle counts")
    parser.add_argument("--repeats", type=int, default=3, help="timed builds per count (default 3)")
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    args = parser.parse_args(argv)
    started, load_before = time.perf_counter(), load_average()
    points = []
    for triangles in sorted(set(args.triangles)):
        points.append(measure(triangles, args.repeats))
        p = points[-1]
        print(
            f"{p['triangles']:>9,} triangles: {p['median_seconds']:.3f} s ({p['one_worker_median_seconds']:.3f} s "
            f"with 1 worker), SAH cost {p['sah_cost']:.1f}",
            flush=True,
        )
    at_target = [p for p in points if p["triangles_requested"] == TARGET_TRIANGLES]
    measured = at_target[0]["median_seconds"] if at_target else None
    result = {
        "load_average_before_after": [load_before, load_average()],
        "scene": "bench/scaling.py's height field and lamp",
        "width": None,
        "height": None,
        "spp": None,
        "max_depth": None,
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
        "wall_seconds": time.perf_counter() - started,
    }
    written = write_result("bvh_build", result, out=args.out, plot=plot)
    print(f"wrote {written['json']} and {written['png'].name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
