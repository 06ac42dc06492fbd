"""Path throughput of the BVH against trac0r's flat box list on the default scene, same run, same adapter.

    python bench/throughput.py            (or: python -m bench.throughput)
    python bench/throughput.py --size 256x256 --spp 8 --repeats 5

Each acceleration gets its own renderer with the same seed, so both trace the same random
numbers. Order of work: warm up (the first dispatch compiles the shader on lavapipe; discarded),
validate two images per acceleration (finite, sane brightness, Cornell structure, and the two
accelerations statistically equal), and only then time `repeats` renders of `spp` samples per
acceleration, interleaved so that background load drifting during the run hits both alike. Every
timed render starts from the seed (Renderer.restart), so all repeats trace the same rays.
Writes bench/results/throughput_<adapter>.json and .png.

Paths/s counts camera paths (pixels x samples); a path is one sample of one pixel, up to
`max_depth` vertices. Rays/s: after timing, the same render is run once more through the path
tracer with ray counters compiled in (wgputrace/render/ray_count.py; the timed kernel has none),
and its image must equal the timed image bit for bit, which shows it traced the same paths; then
rays/s = counted rays / median timed seconds, for camera rays (one per path) and for all rays
(camera, extension and shadow rays).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    # Run as a file: make the repository root importable, as `python -m bench.throughput` does.
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.common import RESULTS_DIR, load_average, result_stem, write_result  # noqa: E402
from wgputrace import Renderer, default_scene  # noqa: E402
from wgputrace.cli import parse_size  # noqa: E402
from wgputrace.gpu.device import describe  # noqa: E402
from wgputrace.render.ray_count import RayCounts, count_rays  # noqa: E402
from wgputrace.scenes import DEFAULT_SCENE  # noqa: E402

ACCELERATIONS = ("bvh", "flat")
BASELINE = "flat"  # the ratio is BVH paths/s over this one's
WARMUP_SPP = 1
VALIDATION_SPP = 1
VALIDATION_IMAGES = 2  # see validate()

# Family-wise false-alarm rate of the BVH-vs-flat tests (channels x image pairs). Sidak's bound holds
# for two-sided z-tests on jointly normal statistics whatever their correlation, and the channels of
# one image are strongly correlated.
AGREEMENT_SIGNIFICANCE = 1e-3
CHANNELS = ("red", "green", "blue")

# A coarse gate on the mean radiance of the whole image, not an accuracy test: the default Cornell
# box at max depth 9 averages about 0.74 here, and a tenth of that or ten times it means lights
# missing, rays missing everything, or path weights blowing up.
MEAN_RADIANCE_BAND = (0.05, 5.0)

RAYS_NOTE = (
    "counted by a second run of the timed render from the same seed through the path tracer with ray "
    "counters compiled in (its image equal to the timed image bit for bit); rays/s = counted rays / "
    "median timed seconds. closest_hit = camera + extension rays; all rays = closest_hit + shadow"
)


@dataclass
class Acceleration:
    """One acceleration's renderer and everything measured with it."""

    name: str
    renderer: Renderer
    run_seconds: list[float] = field(default_factory=list)
    run_cpu_seconds: list[float] = field(default_factory=list)
    timed_image: np.ndarray | None = None  # the last timed render's, for the ray count's check
    rays: RayCounts | None = None

    @property
    def median_seconds(self) -> float:
        return statistics.median(self.run_seconds)

    @property
    def median_cpu_seconds(self) -> float:
        return statistics.median(self.run_cpu_seconds)


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def fresh_image(renderer: Renderer, spp: int, *, from_seed: bool = False) -> tuple[np.ndarray, int, float, float]:
    """Forget earlier samples, render `spp`: (image, dropped samples, wall seconds, process CPU seconds).

    The random sequences continue (new, independent samples), or with `from_seed` start again at
    the seed (the same samples as every other render from the seed). Only the render is timed: the
    clear of the accumulation buffer is waited for before the clock starts, and the read-back of
    the image happens after it stops.
    """
    if from_seed:
        renderer.restart()
    else:
        renderer.reset()
    renderer.context.finish()
    wall, cpu = time.perf_counter(), time.process_time()
    renderer.render(spp)  # returns once every dispatch has finished
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return renderer.image(), renderer.dropped_samples, wall, cpu


def counted_rays(acceleration: Acceleration, spp: int) -> RayCounts:
    """Count the rays of the timed render: the same samples from the seed, through the counting kernel."""
    acceleration.renderer.restart()
    counts = count_rays(acceleration.renderer, spp)
    if not np.array_equal(acceleration.renderer.image(), acceleration.timed_image):
        raise SystemExit(f"{acceleration.name}: the counted render's image differs from the timed one's")
    return counts


def ray_rates(counts: RayCounts, seconds: float) -> dict:
    paths = counts.pixels * counts.samples_per_pixel
    return {
        "camera_rays_per_second": counts.camera / seconds,
        "rays_per_second": counts.total / seconds,
        "rays_per_path": counts.total / paths,
        "rays": {"camera": counts.camera, "extension": counts.extension, "shadow": counts.shadow, "all": counts.total},
    }


def image_checks(image: np.ndarray, nonfinite_samples: int) -> dict:
    """Checks one acceleration's image on its own; "failures" lists what did not hold."""
    finite = bool(np.isfinite(image).all())
    mean = float(np.mean(image, dtype=np.float64)) if finite else math.nan
    third = image.shape[1] // 3
    # Chromaticity (each channel's share of the sum) compares colour, not brightness: the right side
    # is brighter overall because the glossy objects reflect the lamp.
    left = image[:, :third].reshape(-1, 3).sum(axis=0, dtype=np.float64)
    right = image[:, -third:].reshape(-1, 3).sum(axis=0, dtype=np.float64)
    left, right = left / left.sum(), right / right.sum()
    failures = []
    if not finite:
        failures.append(f"{np.count_nonzero(~np.isfinite(image))} image values are NaN or infinite")
    if nonfinite_samples:
        failures.append(f"the shader dropped {nonfinite_samples} samples (non-finite or cut short)")
    low, high = MEAN_RADIANCE_BAND
    if not low <= mean <= high:
        failures.append(f"mean radiance {mean:.4g} is outside the sane band [{low}, {high}]")
    if not left[0] > right[0]:
        failures.append(f"left third is not redder than the right (red share {left[0]:.3f} vs {right[0]:.3f})")
    if not right[1] > left[1]:
        failures.append(f"right third is not greener than the left (green share {right[1]:.3f} vs {left[1]:.3f})")
    return {
        "nonfinite_samples": nonfinite_samples,
        "all_finite": finite,
        "mean_radiance": mean,
        "mean_radiance_band": list(MEAN_RADIANCE_BAND),
        "chromaticity_left_third": left.round(4).tolist(),
        "chromaticity_right_third": right.round(4).tolist(),
        "failures": failures,
    }


def sidak_critical_z(family_significance: float, tests: int) -> float:
    """Two-sided standard-normal bound so that `tests` independent tests together err with that probability."""
    per_test = 1.0 - (1.0 - family_significance) ** (1.0 / tests)
    return statistics.NormalDist().inv_cdf(1.0 - per_test / 2.0)


def agreement(image: np.ndarray, baseline: np.ndarray, z_critical: float) -> dict:
    """Paired z-test per channel that two images have the same expected mean radiance.

    D_p = image_p - baseline_p per pixel p (P pixels). Every pixel has its own random stream, so the
    D_p are independent of each other, and if both accelerations find the same closest hits,
    E[D_p] = 0 for every pixel. The image mean of D then has variance Var(D)/P, estimated by the
    sample variance of the D_p: the standard error comes from the per-pixel spread of the
    differences, which holds only noise, not the picture (the picture cancels in D). With P in the
    hundreds of thousands, mean(D)/SE is standard normal. This holds whatever the correlation
    between the two images, so the same test serves images from the same random numbers (the
    spread is then small and the test sharp; identical images give D = 0 and pass) and from
    independent ones.
    """
    differences = (image.astype(np.float64) - baseline.astype(np.float64)).reshape(-1, 3)
    pixels = len(differences)
    mean = differences.mean(axis=0)
    standard_error = differences.std(axis=0, ddof=1) / math.sqrt(pixels)
    # A zero spread means identical images: then the mean difference is zero as well.
    z = np.divide(mean, standard_error, out=np.zeros(3), where=standard_error > 0)
    failures = [
        f"{channel}: mean radiance differs by {m:.3g} = {score:.2f} standard errors (limit {z_critical:.2f})"
        for channel, m, score in zip(CHANNELS, mean, z, strict=True)
        if abs(score) > z_critical
    ]
    return {
        "mean_difference": mean.tolist(),
        "standard_error": standard_error.tolist(),
        "z": z.tolist(),
        "identical_pixel_fraction": float(np.mean(np.all(differences == 0.0, axis=1))),
        "failures": failures,
    }


def validate(accelerations: dict[str, Acceleration], out: Path, stem: str) -> dict:
    """Render and check two images per acceleration; on failure save them as .npy and exit.

    Both renderers start from the same seed and advance alike, so image k of the BVH and image k of
    the baseline use the same random numbers, while image 1 and image 2 use disjoint stretches of
    every pixel's stream. The BVH's image 1 is compared with the baseline's image 1 (same random
    numbers: expected identical up to ties between equally close triangles) and with the baseline's
    image 2 (independent). Rendering two images each also leaves both streams in step for timing.
    """
    images: dict[str, list[np.ndarray]] = {}
    checks: dict = {}
    for name, acceleration in accelerations.items():
        images[name], checks[name] = [], []
        for _ in range(VALIDATION_IMAGES):
            image, nonfinite, seconds, _ = fresh_image(acceleration.renderer, VALIDATION_SPP)
            images[name].append(image)
            checks[name].append(image_checks(image, nonfinite))
            _log(f"validation image {name}: {seconds:.1f} s, mean radiance {checks[name][-1]['mean_radiance']:.4f}")
    others = [name for name in accelerations if name != BASELINE]
    pairs = {"same_random_numbers": 0, "independent": 1}
    z_critical = sidak_critical_z(AGREEMENT_SIGNIFICANCE, len(others) * len(pairs) * len(CHANNELS))
    checks["agreement"] = {
        "test": "paired z-test on per-pixel differences of the image mean, per channel",
        "significance_family_wise": AGREEMENT_SIGNIFICANCE,
        "sidak_tests": len(others) * len(pairs) * len(CHANNELS),
        "z_critical": z_critical,
        **{
            f"{name}_vs_{BASELINE}": {
                pair: agreement(images[name][0], images[BASELINE][index], z_critical) for pair, index in pairs.items()
            }
            for name in others
        },
    }
    failures = [
        f"{name} image {k + 1}: {text}"
        for name in accelerations
        for k, check in enumerate(checks[name])
        for text in check["failures"]
    ]
    failures += [
        f"{name} vs {BASELINE} ({pair}): {text}"
        for name in others
        for pair in pairs
        for text in checks["agreement"][f"{name}_vs_{BASELINE}"][pair]["failures"]
    ]
    if failures:
        out.mkdir(parents=True, exist_ok=True)
        for name, pictures in images.items():
            for k, image in enumerate(pictures):
                np.save(out / f"{stem}_validation_{name}_{k + 1}.npy", image)
        raise SystemExit(
            f"validation failed, nothing timed (images saved as .npy in {out}):\n  " + "\n  ".join(failures)
        )
    return checks


def plot(path: Path, result: dict) -> None:
    """Bar chart of median paths/s per acceleration, every run as a dot, the ratio written on it."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    names = list(result["accelerations"])
    figure = Figure(figsize=(7.0, 4.8))
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    medians = [result["accelerations"][name]["paths_per_second"] / 1e6 for name in names]
    labels = []
    for name in names:
        structure = result["accelerations"][name]["structure"]
        if structure["kind"] == "bvh":
            shape = f"{structure['node_count']} nodes, depth {structure['depth']}"
        else:
            shape = f"{structure['node_count']} boxes, one per shape"
        labels.append(f"{name}\n{shape}, SAH cost {structure['sah_cost']:.0f}")
    bars = axes.bar(labels, medians, color=["#3b75af", "#aaaaaa"][: len(names)], width=0.55, zorder=2)
    rays = [result["accelerations"][name]["rays_per_second"] / 1e6 for name in names]
    axes.bar_label(
        bars, labels=[f"{m:.3f} M paths/s\n{r:.3f} M rays/s" for m, r in zip(medians, rays, strict=True)], padding=3
    )
    pixels_samples = result["width"] * result["height"] * result["spp"]
    for x, name in enumerate(names):
        runs = [pixels_samples / seconds / 1e6 for seconds in result["accelerations"][name]["run_seconds"]]
        axes.scatter([x] * len(runs), runs, color="black", s=14, zorder=3, label="single runs" if x == 0 else None)
    axes.set_ylabel(f"million paths per second (median of {result['repeats']})")
    axes.set_ylim(0, max(medians) * 1.5)
    axes.grid(axis="y", alpha=0.3, zorder=0)
    axes.legend(loc="upper right")
    axes.text(
        0.5,
        0.9,
        f"BVH / {BASELINE} = {result['bvh_over_flat']:.2f}x",
        transform=axes.transAxes,
        ha="center",
        fontsize=13,
        fontweight="bold",
    )
    axes.text(
        0.5,
        0.84,
        f"({result['bvh_over_flat_process_cpu']:.2f}x in process CPU time per run)",
        transform=axes.transAxes,
        ha="center",
        fontsize=9,
    )
    figure.suptitle(
        f"wgputrace throughput on {result['adapter']['adapter']} ({result['adapter']['backend']})\n"
        f"{result['scene']['name']} ({result['scene']['triangles']} triangles), "
        f"{result['width']}x{result['height']}, {result['spp']} spp, max depth {result['max_depth']}, "
        f"rev {result['git_revision']}",
        fontsize=10,
    )
    figure.tight_layout()
    figure.savefig(path, dpi=120)


def summary(result: dict, json_path: Path, png_path: Path) -> str:
    paths_per_run = result["paths_per_run"]
    lines = [
        f"wgputrace throughput, {result['adapter']['adapter']} ({result['adapter']['backend']}), "
        f"rev {result['git_revision']}",
        f"  {result['scene']['name']}, {result['scene']['triangles']} triangles, {result['width']}x{result['height']}, "
        f"{result['spp']} spp, max depth {result['max_depth']}, median of {result['repeats']}",
    ]
    for name, entry in result["accelerations"].items():
        runs = " ".join(f"{seconds:.2f}" for seconds in entry["run_seconds"])
        lines.append(
            f"  {name:5s} {entry['paths_per_second'] / 1e6:8.4f} M paths/s  {entry['rays_per_second'] / 1e6:8.4f} M rays/s"
            f"  median {entry['median_seconds']:.2f} s  (runs {runs} s)"
        )
    lines += [
        f"  BVH / {BASELINE}: {result['bvh_over_flat']:.2f}x in paths/s "
        f"({result['bvh_over_flat_process_cpu']:.2f}x in process CPU time, which other load hardly changes)",
        f"  rays per path {result['accelerations']['bvh']['rays_per_path']:.2f} "
        f"(camera 1, extension {result['accelerations']['bvh']['rays']['extension'] / paths_per_run:.2f}, "
        f"shadow {result['accelerations']['bvh']['rays']['shadow'] / paths_per_run:.2f}); "
        "camera rays/s = paths/s",
        f"  wall time {result['wall_seconds']:.0f} s; wrote {json_path} and {png_path.name}",
    ]
    return "\n".join(lines)


def parse_arguments(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=parse_size, default=(512, 512), help="WIDTHxHEIGHT (default 512x512)")
    parser.add_argument("--spp", type=int, default=4, help="samples per pixel per timed run (default 4)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per acceleration (default 3)")
    parser.add_argument("--max-depth", type=int, default=9, help="path vertices, Mitsuba's meaning (default 9)")
    parser.add_argument("--seed", type=int, default=1, help="random seed, shared by both accelerations")
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    args = parser.parse_args(argv)
    if args.spp < 1 or args.repeats < 1:
        parser.error(f"--spp and --repeats must be at least 1, got {args.spp} and {args.repeats}")
    if args.size[0] < 3:
        parser.error(f"the Cornell structure check compares image thirds: width must be at least 3, got {args.size[0]}")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_arguments(argv)
    started = time.perf_counter()
    load_before = load_average()
    width, height = args.size
    scene = default_scene()
    accelerations = {
        name: Acceleration(name, Renderer(scene, width, height, seed=args.seed, max_depth=args.max_depth, accel=name))
        for name in ACCELERATIONS
    }
    adapter = describe()
    stem = result_stem("throughput", args.out).name
    _log(f"adapter {adapter['adapter']} ({adapter['backend']}); {width}x{height}, {args.spp} spp x {args.repeats}")

    for name, acceleration in accelerations.items():
        seconds = fresh_image(acceleration.renderer, WARMUP_SPP)[2]
        _log(f"warm-up {name}: {seconds:.1f} s (first dispatch: shader compile or Mesa cache hit)")
    validation = validate(accelerations, args.out, stem)

    for repeat in range(args.repeats):
        for name, acceleration in accelerations.items():
            image, nonfinite, seconds, cpu_seconds = fresh_image(acceleration.renderer, args.spp, from_seed=True)
            if acceleration.timed_image is not None and not np.array_equal(image, acceleration.timed_image):
                raise SystemExit(f"{name}, timed run {repeat + 1}: the image differs from the previous run's")
            acceleration.timed_image = image
            if nonfinite:
                raise SystemExit(
                    f"{name}, timed run {repeat + 1}: the shader dropped {nonfinite} samples (non-finite or cut short)"
                )
            acceleration.run_seconds.append(seconds)
            acceleration.run_cpu_seconds.append(cpu_seconds)
            _log(f"run {repeat + 1}/{args.repeats} {name}: {seconds:.2f} s")

    for name, acceleration in accelerations.items():
        acceleration.rays = counted_rays(acceleration, args.spp)
        _log(f"counted {name}: {acceleration.rays.total / (width * height * args.spp):.2f} rays per path")

    paths = width * height * args.spp
    entries = {}
    for name, acceleration in accelerations.items():
        structure = acceleration.renderer.records.acceleration
        entries[name] = {
            "median_seconds": acceleration.median_seconds,
            "run_seconds": acceleration.run_seconds,
            "run_process_cpu_seconds": acceleration.run_cpu_seconds,
            "median_process_cpu_seconds": acceleration.median_cpu_seconds,
            "paths_per_second": paths / acceleration.median_seconds,
            **ray_rates(acceleration.rays, acceleration.median_seconds),
            "structure": {
                "kind": structure.kind,
                "node_count": structure.node_count,
                "depth": structure.depth,
                "sah_cost": structure.sah_cost(),
                "build_seconds": structure.build_seconds,
            },
        }
    baseline = accelerations[BASELINE]
    result = {
        "adapter_name": baseline.renderer.context.adapter_name,
        "load_average_before_after": [load_before, load_average()],
        "scene": {"name": DEFAULT_SCENE, "triangles": baseline.renderer.triangle_count},
        "width": width,
        "height": height,
        "spp": args.spp,
        "max_depth": args.max_depth,
        "repeats": args.repeats,
        "seed": args.seed,
        "warmup_spp": WARMUP_SPP,
        "validation_spp": VALIDATION_SPP,
        "validation_images_per_acceleration": VALIDATION_IMAGES,
        "paths_per_run": paths,
        "timing": "wall clock of Renderer.render(spp) after reset(), runs interleaved across accelerations; "
        "process CPU seconds include llvmpipe's worker threads",
        "accelerations": entries,
        "bvh_over_flat": entries["bvh"]["paths_per_second"] / entries[BASELINE]["paths_per_second"],
        "bvh_over_flat_per_repeat": [
            flat / bvh for bvh, flat in zip(accelerations["bvh"].run_seconds, baseline.run_seconds, strict=True)
        ],
        # On a CPU adapter other processes steal wall time but hardly change the CPU time a render
        # needs, so this ratio shows whether background load distorted the one above.
        "bvh_over_flat_process_cpu": baseline.median_cpu_seconds / accelerations["bvh"].median_cpu_seconds,
        "rays": RAYS_NOTE,
        "validation": validation,
        "wall_seconds": time.perf_counter() - started,
    }
    paths = write_result("throughput", result, out=args.out, plot=plot)
    print(summary(json.loads(paths["json"].read_text()), paths["json"], paths["png"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
