"""Path throughput of the BVH against trac0r's flat box list on the default scene, same run, same adapter.

    python -m bench.throughput
    python -m bench.throughput --size 256x256 --spp 8 --repeats 5

Both accelerations render from the same seed: a discarded warm-up, then `validate`, then `repeats`
renders of `spp` from the seed, interleaved so that drifting load hits both alike. Paths/s counts
camera paths (pixels x samples). Rays/s: the timed render is replayed through the ray-counting
path tracer (`counted_rays`, which must give the timed image bit for bit), its rays over the median
timed seconds. Writes bench/results/throughput_<adapter>.json and .png.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from bench.timing import Timed, counted_rays, fresh_image, ray_rates
from bench.validation import CHANNELS, agreement, image_failures, sidak_critical_z
from wgputrace import Renderer, default_scene
from wgputrace.scenes import DEFAULT_SCENE

ACCELERATIONS = ("bvh", "flat")
BASELINE = "flat"  # the ratio is BVH paths/s over this one's
WARMUP_SPP = 1
VALIDATION_SPP = 1
VALIDATION_IMAGES = 2  # see validate()
# Family-wise false-alarm rate of the BVH-vs-flat tests (channels x image pairs).
AGREEMENT_SIGNIFICANCE = 1e-3
# The default Cornell box at max depth 9 averages about 0.74 here: a tenth of that or ten times it
# means lights missing, rays missing everything, or path weights blowing up.
MEAN_RADIANCE_BAND = (0.05, 5.0)

RAYS_NOTE = (
    "counted by a second run of the timed render from the same seed through the path tracer with ray "
    "counters compiled in (its image equal to the timed image bit for bit); rays/s = counted rays / "
    "median timed seconds. closest_hit = camera + extension rays; all rays = closest_hit + shadow"
)


def image_checks(image: np.ndarray, dropped: int) -> dict:
    """Checks one acceleration's image on its own; "failures" lists what did not hold."""
    third = image.shape[1] // 3
    # Chromaticity (each channel's share of the sum) compares colour, not brightness: the right side
    # is brighter overall because the glossy objects reflect the lamp.
    left = image[:, :third].reshape(-1, 3).sum(axis=0, dtype=np.float64)
    right = image[:, -third:].reshape(-1, 3).sum(axis=0, dtype=np.float64)
    left, right = left / left.sum(), right / right.sum()
    failures = image_failures(image, dropped, MEAN_RADIANCE_BAND)
    if not left[0] > right[0]:
        failures.append(f"left third is not redder than the right (red share {left[0]:.3f} vs {right[0]:.3f})")
    if not right[1] > left[1]:
        failures.append(f"right third is not greener than the left (green share {right[1]:.3f} vs {left[1]:.3f})")
    return {
        "dropped_samples": dropped,
        "mean_radiance": float(np.mean(image, dtype=np.float64)),
        "chromaticity_left_third": left.round(4).tolist(),
        "chromaticity_right_third": right.round(4).tolist(),
        "failures": failures,
    }


def validate(renderers: dict[str, Renderer], out: Path) -> dict:
    """Render and check two images per acceleration; on failure save them as .npy and exit.

    Both renderers start from the same seed and advance alike, so image k of the BVH and image k of
    the baseline use the same random numbers, while image 1 and image 2 use disjoint stretches of
    every pixel's stream. The BVH's image 1 is compared with the baseline's image 1 (same random
    numbers: expected identical up to ties between equally close triangles) and with the baseline's
    image 2 (independent). Rendering two images each also leaves both streams in step for timing.
    """
    images = {
        name: [fresh_image(renderer, VALIDATION_SPP)[:2] for _ in range(VALIDATION_IMAGES)]
        for name, renderer in renderers.items()
    }
    checks = {name: [image_checks(*pair) for pair in pairs] for name, pairs in images.items()}
    pairs = {"same_random_numbers": 0, "independent": 1}
    tests = (len(renderers) - 1) * len(pairs) * len(CHANNELS)
    z_critical = sidak_critical_z(AGREEMENT_SIGNIFICANCE, tests)
    compared = {
        f"{name}_vs_{BASELINE}": {
            pair: agreement(images[name][0][0], images[BASELINE][index][0], z_critical) for pair, index in pairs.items()
        }
        for name in renderers
        if name != BASELINE
    }
    failures = [
        f"{name} image {k + 1}: {text}"
        for name, found in checks.items()
        for k, check in enumerate(found)
        for text in check["failures"]
    ]
    failures += [
        f"{name} ({pair}): {text}"
        for name, found in compared.items()
        for pair, check in found.items()
        for text in check["failures"]
    ]
    if failures:
        out.mkdir(parents=True, exist_ok=True)
        for name, found in images.items():
            for k, (image, _) in enumerate(found):
                np.save(out / f"throughput_validation_{name}_{k + 1}.npy", image)
        raise SystemExit(
            f"validation failed, nothing timed (images saved as .npy in {out}):\n  " + "\n  ".join(failures)
        )
    means = ", ".join(f"{name} {found[0]['mean_radiance']:.4f}" for name, found in checks.items())
    log(f"validated: mean radiance {means}")
    agreement_checks = {
        "significance_family_wise": AGREEMENT_SIGNIFICANCE,
        "sidak_tests": tests,
        "z_critical": z_critical,
    }
    return {**checks, "agreement": {**agreement_checks, **compared}}


def plot(path: Path, result: dict) -> None:
    """Bar chart of median paths/s per acceleration, every run as a dot, the ratio written on it."""
    chart = figure(7.0, 4.8)
    axes = chart.add_subplot()
    entries = result["accelerations"]
    medians = [entry["paths_per_second"] / 1e6 for entry in entries.values()]
    rays = [entry["rays_per_second"] / 1e6 for entry in entries.values()]
    labels = [
        f"{name}\n{entry['structure']['node_count']} nodes, SAH cost {entry['structure']['sah_cost']:.0f}"
        for name, entry in entries.items()
    ]
    bars = axes.bar(labels, medians, color=["#3b75af", "#aaaaaa"], width=0.55, zorder=2)
    axes.bar_label(
        bars, labels=[f"{m:.3f} M paths/s\n{r:.3f} M rays/s" for m, r in zip(medians, rays, strict=True)], padding=3
    )
    for x, entry in enumerate(entries.values()):
        runs = [entry["paths_per_run"] / seconds / 1e6 for seconds in entry["run_seconds"]]
        axes.scatter([x] * len(runs), runs, color="black", s=14, zorder=3, label="single runs" if x == 0 else None)
    axes.set_ylabel(f"million paths per second (median of {result['repeats']})")
    axes.set_ylim(0, max(medians) * 1.5)
    axes.grid(axis="y", alpha=0.3, zorder=0)
    axes.legend(loc="upper right")
    ratio = f"BVH / {BASELINE} = {result['bvh_over_flat']:.2f}x ({result['bvh_over_flat_process_cpu']:.2f}x in process CPU time)"
    axes.set_title(ratio, fontsize=11)
    save_figure(
        chart,
        path,
        result,
        f"wgputrace throughput, {result['scene']['name']} ({result['scene']['triangles']} triangles), "
        f"{result['width']}x{result['height']}, {result['spp']} spp, max depth {result['max_depth']}",
        dpi=120,
    )


def summary(result: dict) -> str:
    lines = [
        f"wgputrace throughput, {result['adapter']['adapter']}, rev {result['git_revision']}: {result['scene']['name']}, "
        f"{result['width']}x{result['height']}, {result['spp']} spp, max depth {result['max_depth']}, median of {result['repeats']}"
    ]
    for name, entry in result["accelerations"].items():
        runs = " ".join(f"{seconds:.2f}" for seconds in entry["run_seconds"])
        lines.append(
            f"  {name:5s} {entry['paths_per_second'] / 1e6:8.4f} M paths/s  {entry['rays_per_second'] / 1e6:8.4f} M rays/s"
            f"  median {entry['median_seconds']:.2f} s  (runs {runs} s)"
        )
    bvh = result["accelerations"]["bvh"]
    lines += [
        f"  BVH / {BASELINE}: {result['bvh_over_flat']:.2f}x in paths/s "
        f"({result['bvh_over_flat_process_cpu']:.2f}x in process CPU time, which other load hardly changes)",
        f"  rays per path {bvh['rays_per_path']:.2f} (camera 1, extension {bvh['rays']['extension'] / bvh['paths_per_run']:.2f}, "
        f"shadow {bvh['rays']['shadow'] / bvh['paths_per_run']:.2f}); camera rays/s = paths/s",
        f"  wall time {result['wall_seconds']:.0f} s",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(512, 512), spp=4, repeats=3, seed=1)
    parser.add_argument("--max-depth", type=int, default=9, help="path vertices, Mitsuba's meaning (default 9)")
    args = parse(parser, argv, "max_depth")
    if args.size[0] < 3:
        parser.error(f"the Cornell structure check compares image thirds: width must be at least 3, got {args.size[0]}")
    run = Run()
    width, height = args.size
    scene = default_scene()
    renderers = {
        name: Renderer(scene, width, height, seed=args.seed, max_depth=args.max_depth, accel=name)
        for name in ACCELERATIONS
    }
    log(f"{width}x{height}, {args.spp} spp x {args.repeats}")
    for name, renderer in renderers.items():
        log(
            f"warm-up {name}: {fresh_image(renderer, WARMUP_SPP)[2]:.1f} s (first dispatch: shader compile or Mesa cache hit)"
        )
    validation = validate(renderers, args.out)

    paths = width * height * args.spp
    timed = {name: Timed(paths) for name in renderers}
    timed_images: dict[str, np.ndarray] = {}
    for repeat in range(args.repeats):
        for name, renderer in renderers.items():
            image, dropped, wall, cpu = fresh_image(renderer, args.spp, from_seed=True)
            if dropped or not np.array_equal(image, timed_images.setdefault(name, image)):
                raise SystemExit(
                    f"{name}, timed run {repeat + 1}: {dropped} dropped samples or an image unlike the first run's"
                )
            timed[name].add(wall, cpu)
            log(f"run {repeat + 1}/{args.repeats} {name}: {wall:.2f} s")

    entries = {}
    for name, renderer in renderers.items():
        structure = renderer.records.acceleration
        entry = timed[name].entry()
        entries[name] = {
            **entry,
            **ray_rates(counted_rays(renderer, args.spp, timed_images[name]), entry["median_seconds"]),
            "structure": {
                "kind": structure.kind,
                "node_count": structure.node_count,
                "depth": structure.depth,
                "sah_cost": structure.sah_cost(),
                "build_seconds": structure.build_seconds,
            },
        }
        log(f"counted {name}: {entries[name]['rays_per_path']:.2f} rays per path")
    bvh, baseline = timed["bvh"], timed[BASELINE]
    result = {
        "scene": {"name": DEFAULT_SCENE, "triangles": renderers[BASELINE].triangle_count},
        "width": width,
        "height": height,
        "spp": args.spp,
        "max_depth": args.max_depth,
        "repeats": args.repeats,
        "seed": args.seed,
        "warmup_spp": WARMUP_SPP,
        "validation_spp": VALIDATION_SPP,
        "validation_images_per_acceleration": VALIDATION_IMAGES,
        "timing": "wall clock of Renderer.render(spp) from the seed, runs interleaved across accelerations; "
        "process CPU seconds include llvmpipe's worker threads",
        "accelerations": entries,
        "bvh_over_flat": entries["bvh"]["paths_per_second"] / entries[BASELINE]["paths_per_second"],
        "bvh_over_flat_per_repeat": [flat / ours for ours, flat in zip(bvh.wall, baseline.wall, strict=True)],
        # On a CPU adapter other processes steal wall time but hardly change the CPU time a render
        # needs, so this ratio shows whether background load distorted the one above.
        "bvh_over_flat_process_cpu": entries[BASELINE]["median_process_cpu_seconds"]
        / entries["bvh"]["median_process_cpu_seconds"],
        "rays": RAYS_NOTE,
        "validation": validation,
    }
    written = write_result("throughput", result, out=args.out, plot=plot, run=run)
    print(summary(json.loads(written["json"].read_text())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
