"""Time per sample against triangle count, BVH against trac0r's flat list (the thesis's figure 3.5
redone), and GPU memory per triangle at each count.

    python bench/scaling.py                       (or: python -m bench.scaling)
    python bench/scaling.py --triangles 10 1000 100000 --size 128x128 --flat-budget 5

The scene is a gently waving height field (bench/big_mesh.py's) seen from straight above, so it
fills the whole view at every triangle count, lit by a square lamp above the camera and out of
view; only the sheet's subdivision changes. For each count and acceleration: a warm-up render
(compiles the shader once per acceleration, discarded), a validation render (finite, no dropped
samples, mean radiance in a sane band; BVH and flat images from the same random numbers must agree
by the paired z-test of bench/throughput.py), then `repeats` renders of `spp` samples, each from the
seed (Renderer.restart), interleaved across accelerations; time per sample = median seconds / spp.

The flat list is one box holding the whole sheet, so every ray tests every triangle: its time grows
linearly. It runs while its predicted time for the point (warm-up, validation and timed renders; the
last measured time per sample scaled by the triangle count) fits --flat-budget, and never past the adapter's shader loop limit (llvmpipe ends
loops after 65,535 iterations); the result records why each missing point is missing.

Memory, at each count: the scene's GPU buffers (triangles, BVH nodes, materials, light table) as
allocated (with TrackedBuffer's spare capacity) and as used, per triangle; the image's buffers
(random states, accumulation, frame) grow with pixels, not triangles, and are reported apart.

Targets (issue 8): time per sample at 1,000,000 triangles at most 3x that at 1,000; at most 80 GPU
bytes per triangle, BVH included. Writes bench/results/scaling_<adapter>.json and .png.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.big_mesh import height_field  # noqa: E402
from bench.common import RESULTS_DIR, load_average, write_result  # noqa: E402
from bench.throughput import agreement, fresh_image, sidak_critical_z  # noqa: E402
from wgputrace import Camera, Diffuse, Emitter, Renderer, Scene, Shape, make_plane  # noqa: E402
from wgputrace.cli import parse_size  # noqa: E402
from wgputrace.gpu.device import DeviceLimitError  # noqa: E402

TRIANGLE_COUNTS = (10, 100, 1_000, 10_000, 100_000, 1_000_000)
ACCELERATIONS = ("bvh", "flat")
# The targets of issue 8.
TIME_RATIO_TARGET = 3.0  # time per sample at TIME_RATIO_COUNTS[1] over that at TIME_RATIO_COUNTS[0]
TIME_RATIO_COUNTS = (1_000, 1_000_000)
BYTES_PER_TRIANGLE_TARGET = 80.0

SEED = 1
MAX_DEPTH = 9
# The sheet spans [-1, 1]^2 with heights within +-0.1; from this height a 50-degree view sees a
# square of half-width 0.75 at most: the sheet fills the image at every count.
CAMERA_HEIGHT = 1.5
VFOV_DEGREES = 50.0
LAMP_HEIGHT = 3.0
LAMP_SIZE = 1.0
LAMP_EMITTANCE = 20.0
# A coarse gate, not an accuracy test: the lit sheet averages about 0.5 here whatever its
# subdivision; a tenth or ten times that means the lamp is missed or weights blow up.
MEAN_RADIANCE_BAND = (0.05, 5.0)
AGREEMENT_SIGNIFICANCE = 1e-3  # family-wise, over every count where both accelerations run


def sheet_scene(triangles: int) -> Scene:
    """The height field with about `triangles` triangles (2 cells^2), its lamp and camera."""
    cells = max(1, round(math.sqrt(triangles / 2)))
    vertices, faces = height_field(cells)
    sheet = Shape("sheet", vertices[faces], Diffuse("sheet", color=(0.7, 0.7, 0.7)))
    lamp = make_plane(
        (0, LAMP_HEIGHT, 0), (np.pi, 0, 0), (LAMP_SIZE, LAMP_SIZE), Emitter("lamp", emittance=LAMP_EMITTANCE), "lamp"
    )
    # looking straight down, with +z as the picture's up (an exactly vertical up vector would be degenerate)
    camera = Camera.looking_at((0, CAMERA_HEIGHT, -1e-3), (0, 0, 0), vfov_degrees=VFOV_DEGREES)
    return Scene([sheet, lamp], camera)


def memory(renderer: Renderer) -> dict:
    records = renderer.records
    used = {
        "triangles": records.triangles.nbytes,
        "bvh nodes": records.nodes.nbytes,
        "materials": records.materials.nbytes,
        "lights": renderer.lights.entries.nbytes,
    }
    triangles = renderer.triangle_count
    return {
        "scene_bytes_allocated": renderer.gpu_scene_bytes,
        "scene_bytes_used": used,
        "bytes_per_triangle_allocated": renderer.gpu_bytes_per_triangle,
        "bytes_per_triangle_used": sum(used.values()) / triangles,
        "image_bytes": renderer.gpu_image_bytes,
        "image_bytes_per_pixel": sum(renderer.gpu_image_bytes.values()) / (renderer.width * renderer.height),
    }


def image_failures(image: np.ndarray, nonfinite: int) -> list[str]:
    failures = []
    if not np.isfinite(image).all():
        failures.append(f"{np.count_nonzero(~np.isfinite(image))} image values are NaN or infinite")
    if nonfinite:
        failures.append(f"the shader dropped {nonfinite} samples (non-finite or cut short)")
    mean = float(np.mean(image, dtype=np.float64))
    low, high = MEAN_RADIANCE_BAND
    if not low <= mean <= high:
        failures.append(f"mean radiance {mean:.4g} is outside the sane band [{low}, {high}]")
    return failures


def measure_count(triangles: int, args: argparse.Namespace, flat_seconds_per_triangle: float | None) -> dict:
    """One triangle count: build, validate, time; the flat list only where it is allowed and fits the budget."""
    width, height = args.size
    scene = sheet_scene(triangles)
    point = {"triangles": scene.triangle_count, "accelerations": {}, "missing": {}}
    renderers = {}
    for name in ACCELERATIONS:
        if name == "flat" and flat_seconds_per_triangle is not None:
            samples = 1 + args.spp * (1 + args.repeats)  # warm-up, validation, timed renders
            predicted = flat_seconds_per_triangle * scene.triangle_count * samples
            if predicted > args.flat_budget:
                point["missing"][name] = (
                    f"predicted {predicted:.0f} s for {samples} samples per pixel (time per sample grows "
                    f"linearly with the triangles) exceeds the budget of {args.flat_budget:g} s"
                )
                continue
        started = time.perf_counter()
        try:
            renderers[name] = Renderer(scene, width, height, seed=SEED, max_depth=MAX_DEPTH, accel=name)
        except DeviceLimitError as error:
            point["missing"][name] = str(error)
            continue
        setup = time.perf_counter() - started
        warmup = fresh_image(renderers[name], 1, from_seed=True)[2]
        image, nonfinite, _, _ = fresh_image(renderers[name], args.spp, from_seed=True)
        failures = image_failures(image, nonfinite)
        if failures:
            raise SystemExit(f"{scene.triangle_count} triangles, {name}: validation failed, nothing timed: {failures}")
        point["accelerations"][name] = {
            "renderer_setup_seconds": setup,
            "bvh_build_seconds": renderers[name].records.acceleration.build_seconds,
            "node_count": renderers[name].records.acceleration.node_count,
            "warmup_seconds": warmup,
            "mean_radiance": float(np.mean(image, dtype=np.float64)),
            "image": image,
            "run_seconds": [],
            **memory(renderers[name]),
        }
    for _ in range(args.repeats):
        for name, renderer in renderers.items():
            seconds = fresh_image(renderer, args.spp, from_seed=True)[2]
            point["accelerations"][name]["run_seconds"].append(seconds)
    for entry in point["accelerations"].values():
        entry["seconds_per_sample"] = statistics.median(entry["run_seconds"]) / args.spp
    return point


def ratio_to_target(points: list[dict]) -> dict:
    per_sample = {p["triangles_requested"]: p["accelerations"].get("bvh", {}).get("seconds_per_sample") for p in points}
    low, high = (per_sample.get(count) for count in TIME_RATIO_COUNTS)
    ratio = high / low if low and high else None
    return {
        "counts": list(TIME_RATIO_COUNTS),
        "ratio": ratio,
        "target": TIME_RATIO_TARGET,
        "met": None if ratio is None else ratio <= TIME_RATIO_TARGET,
    }


def plot(path: Path, result: dict) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11.0, 4.6))
    FigureCanvasAgg(figure)
    timing, memory_axes = figure.subplots(1, 2)
    styles = {"bvh": ("#3b75af", "o-"), "flat": ("#888888", "s--")}
    for name, (color, style) in styles.items():
        points = [p for p in result["points"] if name in p["accelerations"]]
        if points:
            x = [p["triangles"] for p in points]
            y = [p["accelerations"][name]["seconds_per_sample"] * 1e3 for p in points]
            timing.plot(x, y, style, color=color, label=name)
    for p in result["points"]:
        if "flat" in p["missing"]:
            timing.annotate(
                "flat\nskipped",
                (p["triangles"], 0.03),
                xycoords=("data", "axes fraction"),
                ha="center",
                fontsize=7,
                color="#888888",
            )
    timing.set_xscale("log")
    timing.set_yscale("log")
    timing.set_xlabel("triangles")
    timing.set_ylabel(f"ms per sample per pixel ({result['width']}x{result['height']}, median of {result['repeats']})")
    ratio = result["time_ratio"]
    if ratio["ratio"] is not None:
        timing.set_title(
            f"BVH: time({ratio['counts'][1]:,}) / time({ratio['counts'][0]:,}) = {ratio['ratio']:.2f} "
            f"(target <= {ratio['target']:g})",
            fontsize=9,
        )
    timing.grid(which="both", alpha=0.3)
    timing.legend()
    points = [p for p in result["points"] if "bvh" in p["accelerations"]]
    x = [p["triangles"] for p in points]
    memory_axes.plot(
        x, [p["accelerations"]["bvh"]["bytes_per_triangle_allocated"] for p in points], "o-", label="allocated"
    )
    memory_axes.plot(x, [p["accelerations"]["bvh"]["bytes_per_triangle_used"] for p in points], "^-", label="used")
    memory_axes.axhline(result["bytes_per_triangle_target"], color="grey", linestyle=":", label="target")
    memory_axes.set_xscale("log")
    memory_axes.set_ylim(0, None)
    memory_axes.set_xlabel("triangles")
    memory_axes.set_ylabel("GPU scene bytes per triangle (BVH)")
    memory_axes.set_title(
        f"plus {points[-1]['accelerations']['bvh']['image_bytes_per_pixel']:.0f} B per pixel for the image",
        fontsize=9,
    )
    memory_axes.grid(which="both", alpha=0.3)
    memory_axes.legend()
    figure.suptitle(
        f"wgputrace scaling on {result['adapter']['adapter']} ({result['adapter']['backend']}): {result['scene']}, "
        f"{result['spp']} spp, max depth {result['max_depth']}, rev {result['git_revision']}",
        fontsize=9,
    )
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def parse_arguments(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, nargs="+", default=list(TRIANGLE_COUNTS), help="triangle counts")
    parser.add_argument("--size", type=parse_size, default=(128, 128), help="WIDTHxHEIGHT (default 128x128)")
    parser.add_argument("--spp", type=int, default=2, help="samples per pixel per timed render (default 2)")
    parser.add_argument("--repeats", type=int, default=3, help="timed renders per point (default 3)")
    parser.add_argument(
        "--flat-budget",
        type=float,
        default=120.0,
        help="most predicted seconds of flat rendering per point (default 120)",
    )
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    args = parser.parse_args(argv)
    if min(args.spp, args.repeats, *args.triangles) < 1:
        parser.error("--spp, --repeats and --triangles must be at least 1")
    args.triangles = sorted(set(args.triangles))
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_arguments(argv)
    started, load_before = time.perf_counter(), load_average()
    points = []
    flat_seconds_per_triangle = None
    for triangles in args.triangles:
        point = {"triangles_requested": triangles, **measure_count(triangles, args, flat_seconds_per_triangle)}
        flat = point["accelerations"].get("flat")
        if flat is not None:
            flat_seconds_per_triangle = flat["seconds_per_sample"] / point["triangles"]
        points.append(point)
        timings = ", ".join(f"{n} {e['seconds_per_sample'] * 1e3:.1f} ms" for n, e in point["accelerations"].items())
        print(
            f"{point['triangles']:>9,} triangles: {timings} per sample; "
            f"{point['accelerations']['bvh']['bytes_per_triangle_allocated']:.1f} GPU B/triangle"
            + "".join(f"; {n} skipped: {why}" for n, why in point["missing"].items()),
            file=sys.stderr,
            flush=True,
        )
    both = [p for p in points if len(p["accelerations"]) == len(ACCELERATIONS)]
    z_critical = sidak_critical_z(AGREEMENT_SIGNIFICANCE, max(1, len(both)) * 3)
    failures = []
    for point in both:
        images = {name: entry["image"] for name, entry in point["accelerations"].items()}
        point["bvh_vs_flat"] = agreement(images["bvh"], images["flat"], z_critical)
        failures += [f"{point['triangles']} triangles: {text}" for text in point["bvh_vs_flat"]["failures"]]
    for point in points:
        for entry in point["accelerations"].values():
            del entry["image"]
    if failures:
        raise SystemExit("BVH and flat images disagree (timings not written):\n  " + "\n  ".join(failures))
    largest = points[-1]["accelerations"]["bvh"]
    result = {
        "load_average_before_after": [load_before, load_average()],
        "scene": "height field seen from above, lit by a square lamp",
        "width": args.size[0],
        "height": args.size[1],
        "spp": args.spp,
        "max_depth": MAX_DEPTH,
        "seed": SEED,
        "repeats": args.repeats,
        "flat_budget_seconds": args.flat_budget,
        "timing": "median wall seconds of Renderer.render(spp) from the seed, over spp",
        "points": points,
        "time_ratio": ratio_to_target(points),
        "bytes_per_triangle_target": BYTES_PER_TRIANGLE_TARGET,
        "bytes_per_triangle_at_largest": {
            "triangles": points[-1]["triangles"],
            "allocated": largest["bytes_per_triangle_allocated"],
            "used": largest["bytes_per_triangle_used"],
            "met": largest["bytes_per_triangle_allocated"] <= BYTES_PER_TRIANGLE_TARGET,
        },
        "wall_seconds": time.perf_counter() - started,
    }
    written = write_result("scaling", result, out=args.out, plot=plot)
    ratio = result["time_ratio"]
    if ratio["ratio"] is not None:
        print(f"BVH time per sample, {ratio['counts'][1]:,} / {ratio['counts'][0]:,} triangles: {ratio['ratio']:.2f}")
    print(f"wrote {written['json']} and {written['png'].name} in {result['wall_seconds']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
