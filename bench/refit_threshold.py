"""How much a refit BVH slows rendering as its SAH cost degrades: the measurement behind
wgputrace.render.scene_mirror.REBUILD_DEGRADATION.

    python -m bench.refit_threshold
    python -m bench.refit_threshold --size 64x64 --spp 4 --steps 16 --repeats 7

SPHERES small spheres take a seeded random walk through the Cornell box; one renderer keeps
refitting the BVH it built at step 0, and at each step a fresh Renderer builds a new one. Per step
both pictures must be equal bit for bit, then both are timed, interleaved, keeping the fastest of
`repeats` (other processes on a shared CPU only ever add time). Recorded per step: the refit tree's
SAH cost over its cost when built, seconds per sample of both, their ratio, and what a rebuild
costs. Writes bench/results/refit_threshold_<adapter>.json and .png.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from wgputrace import Diffuse, Renderer, default_scene, make_icosphere, model_matrix
from wgputrace.render import scene_mirror

SEED = 20261123
SPHERES = 24
SPHERE_RADIUS = 0.05
SPHERE_SUBDIVISIONS = 1  # 80 triangles each
# Random-walk step per sphere and axis (the box is 1 wide); positions stay inside BOX_INTERIOR.
STEP = 0.12
BOX_INTERIOR = (np.array([-0.42, -0.05, -0.42]), np.array([0.42, 0.82, 0.42]))


def scene_with_spheres(rng: np.random.Generator):
    scene = default_scene()
    grey = Diffuse("grey", color=(0.6, 0.6, 0.6))
    low, high = BOX_INTERIOR
    spheres = []
    for index in range(SPHERES):
        sphere = make_icosphere((0, 0, 0), (0, 0, 0), SPHERE_RADIUS, SPHERE_SUBDIVISIONS, grey, f"ball{index}")
        sphere.tags["position"] = rng.uniform(low, high)
        sphere.transform = model_matrix(sphere.tags["position"], (0, 0, 0), 1.0)
        spheres.append(sphere)
    scene.add(*spheres)
    return scene, spheres


def walk(spheres, rng: np.random.Generator) -> None:
    low, high = BOX_INTERIOR
    for sphere in spheres:
        sphere.tags["position"] = np.clip(sphere.tags["position"] + rng.normal(0.0, STEP, 3), low, high)
        sphere.transform = model_matrix(sphere.tags["position"], (0, 0, 0), 1.0)


def seconds_per_spp(renderer: Renderer, spp: int) -> float:
    start = time.perf_counter()
    renderer.render(spp)
    return (time.perf_counter() - start) / spp


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(64, 64), spp=4, repeats=7)
    parser.add_argument("--steps", type=int, default=16, help="random-walk steps (default 16)")
    args = parse(parser, argv, "steps")
    run = Run()
    width, height = args.size
    threshold = scene_mirror.REBUILD_DEGRADATION
    scene_mirror.REBUILD_DEGRADATION = float("inf")  # the refit renderer must keep its first tree

    rng = np.random.default_rng(SEED)
    scene, spheres = scene_with_spheres(rng)
    Renderer(scene, width, height, seed=SEED).render(1)  # warm-up: the first dispatch compiles the shader
    refit = Renderer(scene, width, height, seed=SEED)
    steps = []
    for step in range(args.steps + 1):
        if step:
            walk(spheres, rng)
        refit.update()
        start = time.perf_counter()
        fresh = Renderer(scene, width, height, seed=SEED)
        rebuild_seconds = time.perf_counter() - start
        # validate before timing: same picture, bit for bit
        refit.render(1)
        fresh.render(1)
        if not np.array_equal(refit.image(), fresh.image()):
            raise SystemExit(f"step {step}: the refit renderer's image differs from a fresh renderer's")
        times = {"refit": [], "fresh": []}
        for _ in range(args.repeats):
            for name, renderer in (("refit", refit), ("fresh", fresh)):
                times[name].append(seconds_per_spp(renderer, args.spp))
        record = {
            "step": step,
            "degradation": refit._mirror.refitter.degradation,
            "sah_refit": refit._mirror.refitter.cost,
            "sah_fresh": fresh._mirror.refitter.cost,
            "seconds_per_spp_refit": min(times["refit"]),
            "seconds_per_spp_fresh": min(times["fresh"]),
            "all_seconds_per_spp": times,
            "rebuild_seconds": rebuild_seconds,
            "bvh_build_seconds": fresh.records.acceleration.build_seconds,
        }
        record["time_ratio"] = record["seconds_per_spp_refit"] / record["seconds_per_spp_fresh"]
        steps.append(record)
        log(
            f"step {step:2d}: degradation {record['degradation']:.3f}  time ratio {record['time_ratio']:.3f}  "
            f"({record['seconds_per_spp_refit'] * 1e3:.1f} vs {record['seconds_per_spp_fresh'] * 1e3:.1f} ms/spp), "
            f"rebuild {rebuild_seconds * 1e3:.1f} ms"
        )

    degradation = np.array([s["degradation"] for s in steps])
    ratio = np.array([s["time_ratio"] for s in steps])
    # least squares through (1, 1): a tree as good as built renders as fast as a fresh one
    slope = float(np.dot(degradation - 1, ratio - 1) / max(np.dot(degradation - 1, degradation - 1), 1e-12))
    result = {
        "scene": f"default Cornell box + {SPHERES} spheres of {20 * 4**SPHERE_SUBDIVISIONS} triangles, random walk {STEP}",
        "triangles": refit.triangle_count,
        "width": width,
        "height": height,
        "spp": args.spp,
        "max_depth": refit.max_depth,
        "repeats": args.repeats,
        "steps": steps,
        "fit": {"time_ratio_minus_1_per_degradation_minus_1": slope},
        "threshold_in_use": threshold,
    }
    write_result("refit_threshold", result, out=args.out, plot=plot, run=run)
    print(f"slope of (time ratio - 1) over (degradation - 1): {slope:.3f}")
    return 0


def plot(path: Path, result: dict) -> None:
    degradation = np.array([step["degradation"] for step in result["steps"]])
    ratio = np.array([step["time_ratio"] for step in result["steps"]])
    slope = result["fit"]["time_ratio_minus_1_per_degradation_minus_1"]
    threshold = result["threshold_in_use"]
    chart = figure(6.0, 4.0)
    axes = chart.add_subplot()
    axes.plot(degradation, ratio, "o", label="measured")
    line = np.linspace(1.0, degradation.max(), 20)
    axes.plot(line, 1 + slope * (line - 1), "-", label=f"1 + {slope:.2f} (D - 1)")
    axes.axvline(threshold, color="grey", linestyle=":", label=f"REBUILD_DEGRADATION = {threshold}")
    axes.set_xlabel("refit SAH cost / SAH cost when built (D)")
    axes.set_ylabel("render time, refit tree / fresh tree")
    axes.legend()
    save_figure(chart, path, result, result["scene"], fontsize=8, dpi=100)


if __name__ == "__main__":
    sys.exit(main())
