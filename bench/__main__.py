"""The benchmark suite: issue 8's benchmarks, issue 16's denoising and issue 15's environment lighting
on the current adapter, and a summary of every target.

    python -m bench                       (about 45 minutes on lavapipe, 2 cores; denoise about 8, environment 5, restir 4, restir_frames 13)
    python -m bench --quick               (about 5 minutes: smaller images, fewer repeats and counts)
    python -m bench --gpu                 (on a GPU: more samples per timed run, which lasts milliseconds there)
    python -m bench --only scaling bvh_build
    python -m bench --only soak           (not in the default run: 10 minutes of viewer, 10,000 library cycles)

Run from the checkout's root (bench/ is not in the wheel); each benchmark also runs alone as
`python -m bench.<name>`.

Each benchmark writes its own JSON (and chart) to --out; the suite adds suite_<adapter>.json: every
target with its measured value and whether it was met. A benchmark that fails (its validation, or
an error) is recorded as failed and the rest still run (exit status 1). Without mitsuba,
versus_mitsuba and traversal_ceiling skip and convergence leaves out Mitsuba's rows, saying why.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from bench.frame_metrics import flip_missing
from bench.mitsuba import mitsuba_missing
from bench.provenance import RESULTS_DIR, Run, recorded_path
from bench.result_files import SETTINGS_KEYS, result_stem, write_result
from wgputrace.denoise import INSTALL_HINT, denoiser_available


@dataclass(frozen=True)
class Target:
    """One row of the summary: what was measured, against what, and whether it held (None: no target)."""

    benchmark: str
    quantity: str
    measured: str
    target: str = "-"
    met: bool | None = None


def throughput_targets(result: dict) -> list[Target]:
    setting = f"{result['scene']['name']} {result['width']}x{result['height']}"
    rows = []
    for name, entry in result["accelerations"].items():
        rows += [
            Target(
                "throughput", f"{name} paths/s = camera rays/s ({setting})", f"{entry['paths_per_second'] / 1e6:.4f} M"
            ),
            Target("throughput", f"{name} rays/s, all rays ({setting})", f"{entry['rays_per_second'] / 1e6:.4f} M"),
        ]
    rows.append(Target("throughput", "rays per path (bvh)", f"{result['accelerations']['bvh']['rays_per_path']:.2f}"))
    rows.append(Target("throughput", "BVH / flat, paths/s", f"{result['bvh_over_flat']:.2f}x"))
    return rows


def scaling_targets(result: dict) -> list[Target]:
    ratio = result["time_ratio"]
    low, high = ratio["counts"]
    measured = "not measured (count missing)" if ratio["ratio"] is None else f"{ratio['ratio']:.2f}x"
    memory = result["bytes_per_triangle_at_largest"]
    return [
        Target(
            "scaling",
            f"time per sample, {high:,} / {low:,} triangles (bvh)",
            measured,
            f"<= {ratio['target']:g}x",
            ratio["met"],
        ),
        Target(
            "scaling",
            f"GPU bytes per triangle at {memory['triangles']:,} triangles (allocated; used)",
            f"{memory['allocated']:.1f}; {memory['used']:.1f}",
            f"<= {result['bytes_per_triangle_target']:g}",
            memory["met"],
        ),
    ]


def bvh_build_targets(result: dict) -> list[Target]:
    target = result["target"]
    measured = target["measured_seconds"]
    return [
        Target(
            "bvh_build",
            f"build time, {target['triangles']:,} triangles",
            "not measured (count missing)" if measured is None else f"{measured:.2f} s",
            f"< {target['seconds']:g} s",
            target["met"],
        ),
        Target("bvh_build", "SAH cost at the largest count", f"{result['points'][-1]['sah_cost']:.1f}"),
    ]


def versus_mitsuba_targets(result: dict) -> list[Target]:
    paths = result["throughput"]["paths_per_second_ratio"]
    time = result["convergence"]["time_to_equal_rmse"]["ratio"]
    return [
        Target("versus_mitsuba", "paths/s, ours / Mitsuba (512x512)", f"{paths:.3g}", ">= 1", paths >= 1),
        Target("versus_mitsuba", "time to equal RMSE, ours / Mitsuba (128x128)", f"{time:.3g}", "<= 1", time <= 1),
    ]


def traversal_ceiling_targets(result: dict) -> list[Target]:
    ratios = result["ratios"]
    ceiling = ratios["ceiling_over_mitsuba_path"]
    free = ratios["ceiling_free_shadow_rays_over_mitsuba_path"]
    return [
        Target(
            "traversal_ceiling",
            "camera rays/s, ours (max depth 1) / Embree ray_intersect",
            f"{ratios['camera_rays_ours_over_embree_ray_intersect']:.3g}",
        ),
        # the paths/s target above cannot be met while even this bound falls short of it
        Target(
            "traversal_ceiling",
            "ceiling paths/s (ours' camera rays/s / rays per path) / Mitsuba",
            f"{ceiling:.3g}",
            ">= 1",
            ceiling >= 1,
        ),
        Target(
            "traversal_ceiling",
            "the same ceiling with shadow rays free / Mitsuba",
            f"{free:.3g}",
            ">= 1",
            free >= 1,
        ),
    ]


def denoise_targets(result: dict) -> list[Target]:
    usable = str(result["usable_spp"])
    rows = []
    for scene, entry in result["scenes"].items():
        psnr = " / ".join(f"{entry['psnr'][method][usable]['mean']:.1f}" for method in entry["psnr"])
        rows.append(
            Target("denoise", f"PSNR at {usable} spp, raw / a-trous / OIDN / OIDN guided ({scene})", f"{psnr} dB")
        )
        picture = entry["usable_picture"]["oidn_guided"]
        raw = (
            f"{picture['raw_seconds']:.2f} s"
            if picture["raw_seconds"] is not None
            else f"> {picture['raw_last_seconds']:.2f} s (not reached at {picture['raw_last_spp']} spp)"
        )
        rows.append(
            Target(
                "denoise",
                f"usable picture ({picture['target_psnr_db']:.1f} dB): guided OIDN at {usable} spp, raw ({scene})",
                f"{picture['denoised_seconds']:.2f} s, {raw}",
            )
        )
    for method in ("oidn_color", "oidn_guided"):
        # the denoiser's own shift: against the raw picture of the same samples, whose noise cancels
        worst_scene, worst = max(
            ((scene, entry["bias"]) for scene, entry in result["scenes"].items()),
            key=lambda pair: pair[1][method]["against_raw"]["largest"],
        )
        rows.append(
            Target(
                "denoise",
                f"{method}: largest 32-px block mean shift of the same samples at {result['bias_spp']} spp "
                f"(worst scene: {worst_scene})",
                f"{worst[method]['against_raw']['largest']:.2%} (against the reference "
                f"{worst[method]['against_reference']['largest']:.2%}, raw "
                f"{worst['raw_against_reference']['largest']:.2%})",
                f"<= {worst['limit']:.0%}",
                worst[method]["against_raw"]["largest"] <= worst["limit"],
            )
        )
    costs = result["denoiser_cost"]["costs"]
    rows.append(
        Target(
            "denoise",
            f"denoiser s/MP, colour / guided (quality {result['quality']}, {result['denoiser_device']})",
            f"{costs[result['quality'] + '/color']['seconds_per_megapixel']:.2f} / "
            f"{costs[result['quality'] + '/guided']['seconds_per_megapixel']:.2f}",
        )
    )
    return rows


def environment_targets(result: dict) -> list[Target]:
    ratio, target = result["efficiency_ratio"], result["efficiency_target"]
    costs = result["cost_per_sample"]
    cornell = result["cornell"]
    return [
        Target(
            "environment",
            f"efficiency 1/(MSE x s), importance sampled / uniform sphere (sunny map, {result['width']}x{result['height']})",
            f"{ratio:.1f}x",
            f">= {target:g}x",
            ratio >= target,
        ),
        Target(
            "environment",
            "time per sample, map / constant / no environment (sunny scene)",
            f"{costs['map']['over_none']:.3f} / {costs['constant']['over_none']:.3f} / 1",
        ),
        Target(
            "environment",
            f"Cornell box time, current / {cornell['baseline_revision']} (median of paired rounds: process CPU; wall)",
            f"{cornell['ratio_process_cpu']:.3f}; {cornell['ratio_wall']:.3f}",
            f"<= {cornell['target']:g}",
            cornell["ratio_process_cpu"] <= cornell["target"],
        ),
    ]


def convergence_targets(result: dict) -> list[Target]:
    """Judged by process CPU time (both renderers' threads, which the other work on shared cores
    hardly changes; wall-clock ratios of one run swung 2x under load), wall-clock time beside."""
    default, targets = result["default_strategy"], result["targets"]
    by_cpu, by_wall = result["gains_process_cpu"], result["gains"]
    sampler = default.split("/")[1]

    def measured(scene: str, kind: str, key: str) -> tuple[float | None, str]:
        cpu, wall = by_cpu[scene][kind].get(key), by_wall[scene][kind].get(key)
        text = "not measured" if cpu is None else f"{cpu:.3g}"
        return cpu, text if wall is None else f"{text} (wall {wall:.3g})"

    rows = []
    if "cornell" in by_cpu:
        size = "{width}x{height}".format(**result["scenes"]["cornell"])
        for mitsuba_sampler, limit in (("independent", targets["cornell_time_over_mitsuba"]), ("multijitter", None)):
            value, text = measured("cornell", "ours_time_over_mitsuba", mitsuba_sampler)
            rows.append(
                Target(
                    "convergence",
                    f"Cornell box {size}: time to equal RMSE, ours ({default}) / Mitsuba {mitsuba_sampler}",
                    text,
                    "-" if limit is None else f"<= {limit:g}",
                    None if limit is None else value is not None and value <= limit,
                )
            )
    for scene, limit in targets["bdpt_efficiency_over_mis"].items():
        if scene in by_cpu:
            value, text = measured(scene, "bdpt_efficiency_over_mis", sampler)
            rows.append(
                Target(
                    "convergence",
                    f"{scene}: efficiency 1/(MSE x s), bdpt / mis ({sampler} sampler)",
                    text,
                    f">= {limit:g}",
                    value is not None and value >= limit,
                )
            )
    for scene, entry in by_cpu.items():
        for label in entry["sampler_efficiency_over_independent"]:
            text = measured(scene, "sampler_efficiency_over_independent", label)[1]
            rows.append(Target("convergence", f"{scene}: efficiency {label} / independent sampler", text))
    failed = result["validation_failed"]
    rows.append(Target("convergence", "strategies failing validation", ", ".join(failed) or "none", "none", not failed))
    return rows


def cluster_targets(result: dict) -> list[Target]:
    jobs, model = result["jobs"], result["model"]
    rows = [
        Target(
            "cluster",
            f"wall, 1 / 2 workers ({result['batches']} batches of {result['batch_spp']} spp, {result['width']}x{result['height']}, starts included)",
            f"{jobs['1']['wall_seconds']:.2f} / {jobs['2']['wall_seconds']:.2f} s",
        ),
        Target(
            "cluster",
            f"overhead per batch at {model['image']}: worker / driver",
            f"{model['worker_overhead_seconds'] * 1e3:.1f} / {model['driver_seconds_per_batch'] * 1e3:.2f} ms",
        ),
    ]
    for row in model["rows"].values():
        spp = row["batch_spp_for_overhead_under_target"]
        rows.append(
            Target(
                "cluster",
                f"batch keeping overhead < {model['overhead_target']:.0%}, {row['kind']}, {row['workers']} workers (model)",
                "none up to 65536 spp" if spp is None else f"{spp} spp ({row['batch_seconds_then']:.2f} s)",
            )
        )
    return rows


def cluster_unavailable() -> str | None:
    """Why the cluster benchmark cannot run here (no Ray, no network namespace), or None."""
    if importlib.util.find_spec("ray") is None:
        return 'Ray is missing: pip install "wgputrace[ray]"'
    from wgputrace.cluster.sandbox import NamespaceUnavailable, namespace_command

    try:
        namespace_command()
    except NamespaceUnavailable as why:
        return str(why)
    return None


def denoiser_missing() -> str | None:
    """Why the denoising benchmark cannot run here, or None."""
    return None if denoiser_available() else f"Intel Open Image Denoise is missing: {INSTALL_HINT}"


@dataclass(frozen=True)
class Benchmark:
    name: str  # the module bench.<name>, which has main(argv) and files its result under this name
    quick: tuple[str, ...]  # its arguments under --quick
    gpu: tuple[str, ...]  # its arguments under --gpu: more work per timed run, which a GPU ends in milliseconds
    targets: Callable[[dict], list[Target]]
    skip_reason: Callable[[], str | None] = lambda: None
    # runs only when named with --only (the soak: long, and about staying power rather than speed)
    in_default_run: bool = True


def restir_targets(result: dict) -> list[Target]:
    """Issue 27's targets as bench.restir and bench.restir_frames file them: for final renders,
    efficiency (1 / (MSE x s)) of restir over nee on the many-light street and over mis on the
    Cornell box; in motion, the ratio of their mean FLIP at equal time per frame."""
    rows = []
    for key, target in result["targets"].items():
        value = result["measured"].get(key)
        measured = "-" if value is None else f"{value:.2f}x"
        rows.append(
            Target(
                "restir", key.replace("_", " "), measured, f">= {target:g}x", None if value is None else value >= target
            )
        )
    return rows


def soak_targets(result: dict) -> list[Target]:
    limit = f"< {result['flat_growth_mib']:g} MiB"
    rows = []
    if result["viewer"] is not None:
        viewer = result["viewer"]
        trend = viewer["rss_trend"]
        rows += [
            Target(
                "soak",
                f"viewer RSS growth after warm-up ({trend['slope_kib_per_unit']:+.1f} KiB/min, {viewer['minutes']:g} min)",
                f"{trend['fitted_growth_mib']:+.2f} MiB",
                limit,
                trend["flat"],
            ),
            Target("soak", "viewer failures", "; ".join(viewer["failures"]) or "none", "none", not viewer["failures"]),
        ]
    library = result["library"]
    trend = library["rss_trend"]
    growth = library["gpu_growth_after_warmup"]
    return rows + [
        Target(
            "soak",
            f"library RSS growth after warm-up ({trend['slope_kib_per_unit'] * 1000:+.1f} KiB/1000 cycles, "
            f"{library['cycles_done']:,} cycles)",
            f"{trend['fitted_growth_mib']:+.2f} MiB",
            limit,
            trend["flat"],
        ),
        Target(
            "soak",
            "library live wgpu buffers, textures after warm-up",
            f"{growth['buffer_count']:+d}, {growth['texture_count']:+d}",
            "+0, +0",
            growth["buffer_count"] <= 0 and growth["texture_count"] <= 0,
        ),
        Target("soak", "library failures", "; ".join(library["failures"]) or "none", "none", not library["failures"]),
    ]


BENCHMARKS = (
    Benchmark(
        "throughput",
        ("--size", "256x256", "--spp", "1", "--repeats", "2"),
        ("--spp", "256", "--repeats", "5"),
        throughput_targets,
    ),
    Benchmark(
        "scaling",
        (
            "--triangles",
            "10",
            "1000",
            "1000000",
            "--size",
            "64x64",
            "--spp",
            "1",
            "--repeats",
            "2",
            "--flat-budget",
            "10",
        ),
        ("--size", "512x512", "--spp", "64", "--repeats", "5"),
        scaling_targets,
    ),
    Benchmark("bvh_build", ("--triangles", "10", "1000", "1000000", "--repeats", "1"), (), bvh_build_targets),
    Benchmark(
        "versus_mitsuba",
        ("--spp", "1", "--repeats", "1", "--max-spp", "16"),
        (),
        versus_mitsuba_targets,
        skip_reason=mitsuba_missing,
    ),
    Benchmark(
        "traversal_ceiling",
        ("--spp", "1", "--primary-spp", "4", "--repeats", "2"),
        ("--spp", "64", "--primary-spp", "256", "--repeats", "5"),
        traversal_ceiling_targets,
        skip_reason=mitsuba_missing,
    ),
    Benchmark(
        "denoise",
        (
            "--scenes",
            "cornell",
            "glossy_spheres",
            "glass_grazing",
            "--repeats",
            "1",
            "--bias-spp",
            "256",
            "--cap-spp",
            "256",
            "--rounds",
            "2",
            "--round-spp",
            "4",
            "--denoise-size",
            "256x256",
            "--denoise-repeats",
            "2",
        ),
        (
            "--repeats",
            "8",
            "--bias-spp",
            "16384",
            "--cap-spp",
            "65536",
            "--round-spp",
            "256",
            "--denoise-size",
            "1024x1024",
        ),
        denoise_targets,
        skip_reason=denoiser_missing,
    ),
    Benchmark(
        "environment",
        (
            "--size",
            "64",
            "--reference-spp",
            "1024",
            "--repeats",
            "3",
            "--cost-rounds",
            "3",
            "--cornell-size",
            "128",
            "--cornell-spp",
            "8",
            "--cornell-rounds",
            "5",
        ),
        ("--spp", "256", "--reference-spp", "65536", "--validation-spp", "1024", "--cornell-spp", "1024"),
        environment_targets,
    ),
    Benchmark(
        "convergence",
        ("--scenes", "cornell", "caustic", "--integrators", "mis", "bdpt", "--max-spp", "64"),
        ("--max-spp", "4096", "--runs", "2"),
        convergence_targets,
    ),
    Benchmark(
        "restir",
        ("--scenes", "night_street", "cornell", "--no-sweep", "--max-spp", "64"),
        ("--max-spp", "4096"),
        restir_targets,
    ),
    Benchmark(
        "restir_frames",
        ("--scenes", "street", "cornell", "--frames", "10", "--size", "160x120"),
        ("--size", "1920x1080", "--budget", "0.0167"),
        restir_targets,
        skip_reason=flip_missing,
    ),
    Benchmark("soak", ("--minutes", "1", "--cycles", "1000"), (), soak_targets, in_default_run=False),
    Benchmark(
        "cluster",
        ("--size", "64x64", "--batch-spp", "2", "--batches", "4", "--repeats", "1"),
        ("--size", "512x512", "--batch-spp", "256"),
        cluster_targets,
        skip_reason=cluster_unavailable,
    ),
)


def run(benchmark: Benchmark, preset: str | None, out: Path) -> dict:
    """Run one benchmark; its outcome ("ok", "skipped", "failed"), seconds, result file and targets."""
    reason = benchmark.skip_reason()
    if reason:
        return {"outcome": "skipped", "reason": reason, "targets": []}
    argv = [*(benchmark.quick if preset == "quick" else benchmark.gpu if preset == "gpu" else ()), "--out", str(out)]
    path = result_stem(benchmark.name, out).with_suffix(".json")
    started = time.time()
    try:
        status = importlib.import_module(f"bench.{benchmark.name}").main(argv)
    except SystemExit as stop:  # validation failures and argument errors end a benchmark this way
        status = stop.code
    except Exception:  # the suite goes on; the failure is recorded with its traceback
        return {"outcome": "failed", "reason": traceback.format_exc(), "seconds": time.time() - started, "targets": []}
    seconds = time.time() - started
    if status not in (0, None):
        return {"outcome": "failed", "reason": f"exit status {status}", "seconds": seconds, "targets": []}
    if not path.exists() or path.stat().st_mtime < started:
        # versus_mitsuba, for one, files a skip under another name
        return {"outcome": "skipped", "reason": f"wrote no {path.name}", "seconds": seconds, "targets": []}
    result = json.loads(path.read_text())
    return {
        "outcome": "ok",
        "git_revision": result["git_revision"],
        "created_utc": result["environment"]["created_utc"],
        "seconds": seconds,
        "result_file": recorded_path(path),
        "settings": {key: result.get(key) for key in SETTINGS_KEYS},
        "targets": [vars(target) for target in benchmark.targets(result)],
    }


def table(runs: dict[str, dict]) -> str:
    rows = [("benchmark", "quantity", "measured", "target", "met")]
    for name, entry in runs.items():
        if entry["outcome"] != "ok":
            rows.append((name, entry["outcome"], entry["reason"].strip().splitlines()[-1], "", ""))
        for target in entry["targets"]:
            met = {True: "yes", False: "NO", None: ""}[target["met"]]
            rows.append((target["benchmark"], target["quantity"], target["measured"], target["target"], met))
    widths = [max(len(row[column]) for row in rows) for column in range(5)]
    return "\n".join("  ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)) for row in rows)


def main(argv: list[str] | None = None) -> int:
    names = [benchmark.name for benchmark in BENCHMARKS]
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", choices=names, metavar="NAME", help=f"run only these: {', '.join(names)}")
    presets = parser.add_mutually_exclusive_group()
    presets.add_argument("--quick", action="store_true", help="smaller settings: about 5 minutes on lavapipe")
    presets.add_argument("--gpu", action="store_true", help="more samples per timed run, for a GPU")
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    args = parser.parse_args(argv)
    suite = Run()
    # --only updates its benchmarks' rows and keeps the others' from earlier runs (each row says when)
    previous = result_stem("suite", args.out).with_suffix(".json")
    runs = json.loads(previous.read_text())["benchmarks"] if args.only and previous.exists() else {}
    for benchmark in BENCHMARKS:
        if benchmark.name not in args.only if args.only else not benchmark.in_default_run:
            continue
        print(f"== {benchmark.name}", file=sys.stderr, flush=True)
        preset = "quick" if args.quick else "gpu" if args.gpu else None
        runs[benchmark.name] = {**run(benchmark, preset, args.out), "preset": preset}
    # each benchmark records its own settings; see "benchmarks"
    written = write_result("suite", {**dict.fromkeys(SETTINGS_KEYS), "benchmarks": runs}, out=args.out, run=suite)
    print(table(runs))
    print(f"suite: {json.loads(written['json'].read_text())['wall_seconds']:.0f} s; wrote {written['json']}")
    return 1 if any(entry["outcome"] == "failed" for entry in runs.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
