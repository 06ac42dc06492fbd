"""Side by side with Mitsuba 3 in one process: paths/s on the Cornell box at 512x512, and the time
each renderer needs to reach the same RMSE against the reference at 128x128.

    python -m bench.versus_mitsuba
    python -m bench.versus_mitsuba --spp 4 --repeats 3 --max-spp 256 --runs 1

Mitsuba runs its `llvm_ad_rgb` variant (drjit's LLVM backend: libLLVM >= 16) with its `path`
integrator on the scene `mitsuba_scene` builds from ours; ours runs Renderer (MIS). Same scene,
resolution, samples per pixel and max depth (the reference's). Compilation is measured apart
(`measure_compile`); each part validates both renderers against the reference before it times
(`validate_both`), and interleaves their timed renders so that drifting load hits both alike.
Without mitsuba or LLVM >= 16 this skips, recording why. Writes
bench/results/versus_mitsuba_<adapter>.json and .png.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import add_max_spp, argument_parser, log, parse
from bench.error_curves import FIT_MIN_SPP, checkpoints, curves, error_at, errors, fit_power_law, seconds_to_reach
from bench.mitsuba import MITSUBA_SEED_START, MitsubaSide, add_mitsuba_variant, mitsuba_missing, threads
from bench.provenance import Run
from bench.result_files import record_skip, result_stem, write_result
from bench.timing import Timed, fresh_image
from bench.validation import CHANNELS, image_failures
from wgputrace import Renderer, load_scene
from wgputrace.reference.mitsuba_scene import libllvm_path, load_mitsuba
from wgputrace.testing.image_statistics import Estimate, compare_blocks
from wgputrace.testing.references import STORAGE_RTOL, Reference, load_reference
from wgputrace.testing.stats import sidak

NAME = "versus_mitsuba"
SCENE = "cornell"
OURS, MITSUBA = "wgputrace", "mitsuba"
THROUGHPUT_SIZE = 512
CONVERGENCE_SIZE = 128  # the reference's: errors are measured pixel by pixel against it
COMPILE_PROBE_SIZE = 8
VALIDATION_BATCHES = 8
# Samples per pixel of each validation batch, per image size: about 2 million paths per renderer
# and size, the sample count the render tests test the Cornell box with.
VALIDATION_SPP = {THROUGHPUT_SIZE: 1, CONVERGENCE_SIZE: 16}
# Block sizes (at the reference's resolution) and family-wise level, as the render tests use.
VALIDATION_BLOCKS = (8, CONVERGENCE_SIZE)
VALIDATION_SIGNIFICANCE = 1e-3


def empty_compile_caches(folder: Path) -> dict:
    """Point drjit's kernel cache and Mesa's shader cache at empty folders, so that both warm-ups
    compile for real; each library reads its setting when it starts, so this holds only for those
    not started yet in this process (the result says which)."""
    from wgputrace.gpu import device

    empty = {OURS: device._context is None, MITSUBA: "drjit" not in sys.modules}
    if empty[MITSUBA]:
        os.environ["DRJIT_CACHE_DIR"] = str(folder / "drjit")
    if empty[OURS]:
        os.environ["MESA_SHADER_CACHE_DIR"] = str(folder / "mesa")
    return empty


def validate(label: str, batches: list[np.ndarray], reference: Reference, per_test: float) -> dict:
    """`batches` (independent images), averaged down to the reference's size where larger (exact
    for a box filter), Welch-tested against the reference per block and channel as the render tests
    do; exits on failure."""
    estimate = Estimate.from_batches(np.stack(batches))
    factor = estimate.mean.shape[0] // reference.estimate.mean.shape[0]
    if factor > 1:
        estimate = estimate.downsampled(factor)
    failures = [text for batch in batches for text in image_failures(batch, 0)][:1]
    worst = 1.0
    for block in VALIDATION_BLOCKS:
        reference_blocks = Estimate(reference.estimate.mean, np.zeros_like(reference.estimate.mean), np.inf)
        tolerance = STORAGE_RTOL * np.abs(reference_blocks.blocks(block)[0])
        comparison = compare_blocks(estimate, reference.estimate, block, tolerance)
        failing = comparison.p_value < per_test
        worst = min(worst, float(comparison.p_value.min()))
        if failing.any():
            z = comparison.z[failing]
            failures.append(
                f"{int(failing.sum())} of {failing.size} {block}x{block}-block tests reject the reference's "
                f"expectation at p < {per_test:.3g} (z from {z.min():.2f} to {z.max():.2f})"
            )
    if failures:
        raise SystemExit(f"{label}: validation failed, nothing timed: {'; '.join(failures)}")
    log(f"validated {label}: smallest p-value {worst:.3g} (limit {per_test:.3g})")
    return {"batches": len(batches), "smallest_p_value": worst, "per_test_significance": per_test}


def validate_both(ours: Renderer, mitsuba: MitsubaSide, depth: int, reference: Reference, per_test: float) -> dict:
    """Both renderers' images at `ours`' size against the reference, VALIDATION_BATCHES each."""
    size, spp = ours.width, VALIDATION_SPP[ours.width]
    validation = {
        OURS: validate(
            f"ours {size}x{size}", [fresh_image(ours, spp)[0] for _ in range(VALIDATION_BATCHES)], reference, per_test
        ),
        MITSUBA: validate(
            f"Mitsuba {size}x{size}",
            [mitsuba.render(size, depth, spp)[0] for _ in range(VALIDATION_BATCHES)],
            reference,
            per_test,
        ),
    }
    mitsuba.kernel_report()
    return validation


def measure_compile(mitsuba: MitsubaSide, args: argparse.Namespace) -> dict:
    """Each renderer's first render minus its second, at COMPILE_PROBE_SIZE and 1 spp: the shader
    compile (or JIT trace and compile) and first-use set-up, with so little rendering in either
    that background load hardly moves the difference. Both compiled kernels serve every size."""
    size, depth = COMPILE_PROBE_SIZE, args.max_depth
    ours = Renderer(load_scene(SCENE), size, size, seed=args.seed, max_depth=depth)
    seconds = {OURS: [fresh_image(ours, 1)[2] for _ in range(2)], MITSUBA: [mitsuba.render(size, depth, 1)[1]]}
    kernels = mitsuba.kernel_report()
    seconds[MITSUBA].append(mitsuba.render(size, depth, 1)[1])
    mitsuba.kernel_report()
    result = {
        name: {"first_render_seconds": first, "second_render_seconds": second, "compile_seconds": first - second}
        for name, (first, second) in seconds.items()
    }
    result[MITSUBA]["kernels"] = kernels
    log(f"compile: ours {result[OURS]['compile_seconds']:.2f} s, Mitsuba {result[MITSUBA]['compile_seconds']:.2f} s")
    return result


def measure_throughput(mitsuba: MitsubaSide, reference: Reference, args: argparse.Namespace, per_test: float) -> dict:
    """Paths/s at THROUGHPUT_SIZE: a discarded warm-up each, validation, then `repeats` fresh renders
    of `spp`, ours and Mitsuba's in turn; medians."""
    size, depth = THROUGHPUT_SIZE, args.max_depth
    ours = Renderer(load_scene(SCENE), size, size, seed=args.seed, max_depth=depth)
    first = {OURS: fresh_image(ours, args.spp)[2], MITSUBA: mitsuba.render(size, depth, args.spp)[1]}
    warmup_kernels = mitsuba.kernel_report()
    log(f"warm-up {size}x{size}: ours {first[OURS]:.2f} s, Mitsuba {first[MITSUBA]:.2f} s")
    validation = validate_both(ours, mitsuba, depth, reference, per_test)
    paths = size * size * args.spp
    timed = {OURS: Timed(paths), MITSUBA: Timed(paths)}
    for repeat in range(args.repeats):
        image, dropped, wall, cpu = fresh_image(ours, args.spp)
        timed[OURS].add(wall, cpu)
        failures = image_failures(image, dropped)
        image, wall, cpu = mitsuba.render(size, depth, args.spp)
        timed[MITSUBA].add(wall, cpu)
        failures += [f"Mitsuba: {text}" for text in image_failures(image, 0)]
        if failures:
            raise SystemExit(f"timed run {repeat + 1}: {'; '.join(failures)}")
        log(f"run {repeat + 1}/{args.repeats}: ours {timed[OURS].wall[-1]:.2f} s, Mitsuba {wall:.2f} s")
    renderers = {
        name: {**timed[name].entry(), "warmup_seconds": first[name], "validation": validation[name]} for name in timed
    }
    renderers[MITSUBA]["warmup_kernels"] = warmup_kernels
    renderers[MITSUBA]["timed_kernels"] = mitsuba.compiled_nothing("timed renders")
    return {
        "width": size,
        "height": size,
        "spp": args.spp,
        "repeats": args.repeats,
        "paths_per_run": paths,
        "renderers": renderers,
        "paths_per_second_ratio": renderers[OURS]["paths_per_second"] / renderers[MITSUBA]["paths_per_second"],
        "process_cpu_ratio": statistics.median(timed[MITSUBA].cpu) / statistics.median(timed[OURS].cpu),
    }


def measure_convergence(mitsuba: MitsubaSide, reference: Reference, args: argparse.Namespace, per_test: float):
    """RMSE against time at the reference's size: ours renders progressively (render time summed
    over the checkpoints), Mitsuba each checkpoint as one fresh render at that spp (its usual use
    and its fastest); `time_to_equal_rmse` reads the two curves."""
    size, depth = CONVERGENCE_SIZE, args.max_depth
    mean, variance = reference.estimate.mean, reference.estimate.variance
    ours = Renderer(load_scene(SCENE), size, size, seed=args.seed, max_depth=depth)
    fresh_image(ours, 1)  # warm-up (the pipeline for this size), discarded
    mitsuba.render(size, depth, 1)
    warmup_kernels = mitsuba.kernel_report()
    validation = validate_both(ours, mitsuba, depth, reference, per_test)
    rows = []
    for run in range(args.runs):
        ours.reset()
        ours.context.finish()
        seconds = cpu_seconds = 0.0
        for checkpoint in checkpoints(args.max_spp):
            wall, cpu = time.perf_counter(), time.process_time()
            ours.render(checkpoint - ours.samples_per_pixel)
            seconds += time.perf_counter() - wall
            cpu_seconds += time.process_time() - cpu
            image = ours.image()
            theirs, wall, cpu = mitsuba.render(size, depth, checkpoint)
            failures = image_failures(image, ours.dropped_samples) + image_failures(theirs, 0)
            if failures:
                raise SystemExit(f"run {run + 1}, {checkpoint} spp: {'; '.join(failures)}")
            row = {"scene": SCENE, "run": run + 1, "spp": checkpoint}
            rows.append(
                row
                | {"integrator": OURS, "seconds": seconds, "cpu_seconds": cpu_seconds}
                | errors(image, mean, variance)
            )
            rows.append(
                row | {"integrator": MITSUBA, "seconds": wall, "cpu_seconds": cpu} | errors(theirs, mean, variance)
            )
        log(
            f"run {run + 1}/{args.runs}: RMSE at {args.max_spp} spp ours {rows[-2]['rmse']:.4g}, Mitsuba {rows[-1]['rmse']:.4g}"
        )
    timed_kernels = mitsuba.compiled_nothing("timed renders")
    # curves() groups by scene and "integrator": here that column names the renderer
    by_renderer = {curve["integrator"]: curve for curve in curves(rows).values()}
    # the same in process CPU time (both renderers' worker threads run in this process), which
    # other load on the shared cores hardly changes
    by_renderer_cpu = {
        curve["integrator"]: curve for curve in curves([row | {"seconds": row["cpu_seconds"]} for row in rows]).values()
    }
    return {
        "width": size,
        "height": size,
        "max_spp": args.max_spp,
        "runs": args.runs,
        "timing": "ours: Renderer.render summed over the progressive checkpoints; Mitsuba: one fresh render "
        "per checkpoint at that spp; image read-backs not timed",
        "validation": validation,
        "warmup_kernels": warmup_kernels,
        "timed_kernels": timed_kernels,
        "curves": by_renderer,
        "time_to_equal_rmse": time_to_equal_rmse(by_renderer[OURS], by_renderer[MITSUBA]),
        "process_cpu_time_to_equal_rmse": time_to_equal_rmse(by_renderer_cpu[OURS], by_renderer_cpu[MITSUBA]),
        "rows": rows,
    }


def time_to_equal_rmse(ours: dict, theirs: dict) -> dict:
    """Times for both curves to reach a common RMSE, from power laws fitted to RMSE against time
    (`fit_power_law`); the level is the larger of the two fitted final RMSEs, which both
    curves reach inside their measured time range."""
    fits = {OURS: fit_power_law(ours, "rmse"), MITSUBA: fit_power_law(theirs, "rmse")}
    final = {
        name: error_at(slope, intercept, curve["seconds"][-1])
        for (name, (slope, intercept)), curve in zip(fits.items(), (ours, theirs), strict=True)
    }
    level = max(final.values())
    seconds = {name: seconds_to_reach(slope, intercept, level) for name, (slope, intercept) in fits.items()}
    return {
        "rmse": level,
        "seconds": seconds,
        "fitted_slope_rmse_vs_seconds": {name: fit[0] for name, fit in fits.items()},
        "fitted_final_rmse": final,
        "ratio": seconds[OURS] / seconds[MITSUBA],
    }


def plot(path: Path, result: dict) -> None:
    chart = figure(12.0, 5.0)
    error_axes, bar_axes = chart.subplots(1, 2, gridspec_kw={"width_ratios": [1.4, 1.0]})
    colors = {OURS: "#3b75af", MITSUBA: "#c4452c"}
    convergence = result["convergence"]
    equal = convergence["time_to_equal_rmse"]
    for name, curve in convergence["curves"].items():
        error_axes.loglog(curve["seconds"], curve["rmse"], "o", markersize=4, color=colors[name], label=name)
        slope, intercept = fit_power_law(curve, "rmse")
        fitted = [s for s, spp in zip(curve["seconds"], curve["spp"], strict=True) if spp >= FIT_MIN_SPP]
        error_axes.loglog(fitted, np.exp(intercept + slope * np.log(fitted)), "-", color=colors[name], alpha=0.6)
        error_axes.axvline(equal["seconds"][name], color=colors[name], linestyle=":", linewidth=1)
    error_axes.axhline(
        equal["rmse"], color="grey", linestyle="--", linewidth=1, label=f"common RMSE {equal['rmse']:.3g}"
    )
    error_axes.set_xlabel("render time (s)")
    error_axes.set_ylabel("RMSE against the reference (its variance subtracted)")
    error_axes.set_title(
        f"{convergence['width']}x{convergence['height']}, 1..{convergence['max_spp']} spp: "
        f"time to equal RMSE ours / Mitsuba = {equal['ratio']:.2f} "
        f"(process CPU {convergence['process_cpu_time_to_equal_rmse']['ratio']:.2f})",
        fontsize=10,
    )
    error_axes.grid(which="both", alpha=0.3)
    error_axes.legend(fontsize=8)
    throughput = result["throughput"]
    names = list(throughput["renderers"])
    medians = [throughput["renderers"][name]["paths_per_second"] / 1e6 for name in names]
    bars = bar_axes.bar(names, medians, color=[colors[name] for name in names], width=0.5, zorder=2)
    bar_axes.bar_label(bars, labels=[f"{m:.3f} M paths/s" for m in medians], padding=3)
    for x, name in enumerate(names):
        runs = [throughput["paths_per_run"] / s / 1e6 for s in throughput["renderers"][name]["run_seconds"]]
        bar_axes.scatter([x] * len(runs), runs, color="black", s=12, zorder=3)
    bar_axes.set_ylim(0, max(medians) * 1.25)
    bar_axes.set_ylabel(f"million paths per second (median of {throughput['repeats']}, dots: runs)")
    bar_axes.set_title(
        f"{throughput['width']}x{throughput['height']}, {throughput['spp']} spp: "
        f"ours / Mitsuba = {throughput['paths_per_second_ratio']:.3f} (process CPU {throughput['process_cpu_ratio']:.3f})",
        fontsize=10,
    )
    bar_axes.grid(axis="y", alpha=0.3, zorder=0)
    title = (
        f"wgputrace vs Mitsuba {result['mitsuba']} {result['variant']} (path), {result['scene']}, max depth "
        f"{result['max_depth']}; threads {', '.join(f'{k} {v}' for k, v in result['threads'].items())}"
    )
    save_figure(chart, path, result, title)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, spp=4, repeats=3, seed=1)
    add_max_spp(parser, 256)
    parser.add_argument("--runs", type=int, default=1, help="convergence runs per renderer (default 1)")
    add_mitsuba_variant(parser)
    args = parse(parser, argv, "runs")
    reference = load_reference(SCENE)
    if (reference.metadata["width"], reference.metadata["height"]) != (CONVERGENCE_SIZE, CONVERGENCE_SIZE):
        raise SystemExit(
            f"the {SCENE} reference is not {CONVERGENCE_SIZE}x{CONVERGENCE_SIZE}: errors are measured at that size"
        )
    args.max_depth = reference.metadata["max_depth"]
    settings = {
        "scene": SCENE,
        "width": THROUGHPUT_SIZE,
        "height": THROUGHPUT_SIZE,
        "spp": args.spp,
        "max_depth": args.max_depth,
    }
    reason = mitsuba_missing(args.mitsuba_variant)
    if reason:
        return record_skip(NAME, settings, reason, args.out)
    run = Run()
    # before anything starts the GPU device or drjit
    caches = tempfile.TemporaryDirectory(prefix="versus-mitsuba-caches-")
    empty_caches = empty_compile_caches(Path(caches.name))
    import drjit

    mitsuba = MitsubaSide(load_mitsuba(args.mitsuba_variant), drjit, SCENE)
    drjit.set_flag(drjit.JitFlag.KernelHistory, True)
    # Sidak over both parts, both renderers, every block size and channel
    tests = 2 * 2 * len(CHANNELS) * sum((CONVERGENCE_SIZE // block) ** 2 for block in VALIDATION_BLOCKS)
    per_test = sidak(VALIDATION_SIGNIFICANCE, tests)
    compile_times = measure_compile(mitsuba, args)
    throughput = measure_throughput(mitsuba, reference, args, per_test)
    convergence = measure_convergence(mitsuba, reference, args, per_test)
    # Mitsuba compiles a few size-dependent kernels (film, reductions) at each new image size
    warmups = (
        compile_times[MITSUBA]["kernels"],
        throughput["renderers"][MITSUBA]["warmup_kernels"],
        convergence["warmup_kernels"],
    )
    compile_times[MITSUBA]["llvm_ms_all_warmups"] = sum(k["codegen_ms"] + k["llvm_backend_ms"] for k in warmups)
    result = {
        **settings,
        "integrators": {OURS: "mis", MITSUBA: "path"},
        "mitsuba": mitsuba.mi.__version__,
        "drjit": drjit.__version__,
        "variant": args.mitsuba_variant,
        "libllvm": libllvm_path(),
        "reference": reference.metadata,
        "mitsuba_seed_start": MITSUBA_SEED_START,
        "threads": threads(drjit),
        "compile_caches_empty_at_start": empty_caches,
        "validation": {
            "test": "Welch t-test per block and channel against the reference (wgputrace/testing/image_statistics.py)",
            "batches": VALIDATION_BATCHES,
            "spp_per_batch": VALIDATION_SPP,
            "blocks": VALIDATION_BLOCKS,
            "significance_family_wise": VALIDATION_SIGNIFICANCE,
            "sidak_tests": tests,
        },
        "compile": compile_times,
        "throughput": throughput,
        "convergence": convergence,
    }
    caches.cleanup()
    write_result(NAME, result, out=args.out, plot=plot, run=run)
    # a skip recorded earlier no longer holds
    result_stem(f"{NAME}_skipped", args.out).with_suffix(".json").unlink(missing_ok=True)
    equal = convergence["time_to_equal_rmse"]
    print(
        f"paths/s at {THROUGHPUT_SIZE}x{THROUGHPUT_SIZE}, {args.spp} spp: ours "
        f"{throughput['renderers'][OURS]['paths_per_second'] / 1e6:.4f} M, Mitsuba "
        f"{throughput['renderers'][MITSUBA]['paths_per_second'] / 1e6:.4f} M, ratio {throughput['paths_per_second_ratio']:.3f} "
        f"(process CPU {throughput['process_cpu_ratio']:.3f})\n"
        f"time to RMSE {equal['rmse']:.4g} at {convergence['width']}x{convergence['height']}: ours "
        f"{equal['seconds'][OURS]:.2f} s, Mitsuba {equal['seconds'][MITSUBA]:.2f} s, ratio {equal['ratio']:.3f} "
        f"(process CPU {convergence['process_cpu_time_to_equal_rmse']['ratio']:.3f})\n"
        f"compile apart: ours {compile_times[OURS]['compile_seconds']:.2f} s, Mitsuba "
        f"{compile_times[MITSUBA]['compile_seconds']:.2f} s ({compile_times[MITSUBA]['kernels']['compiled']} kernels; "
        f"{compile_times[MITSUBA]['llvm_ms_all_warmups'] / 1e3:.2f} s of trace and LLVM compile over all sizes)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
