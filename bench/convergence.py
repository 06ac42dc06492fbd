"""Error against time: RMSE and relative MSE of our image against the Mitsuba 3 reference, as
functions of samples per pixel and of render time, for the Cornell box and the tiny-light scene.

    python -m bench.convergence
    python -m bench.convergence --max-spp 64 --runs 1 --integrators mis

For each scene and integrator: a validation render first (finite, no dropped samples, image mean
equal to the reference's within a z-test; its first dispatch is the shader compile, so it is the
warm-up too), then `runs` progressive renders from different seeds, the image read back at 1, 2,
4, ... max-spp samples per pixel. Only Renderer.render is timed; read-backs are not. The reference
(tests/references/<scene>.npz, 128x128) is noisy itself; its variance is subtracted (bench/common.py's
`errors`), so the curves show our error alone. A converging unbiased estimator has RMSE ~ spp^-0.5
(slope -0.5 on log-log axes) and relative MSE ~ spp^-1; the height of a curve is the efficiency
later work improves. Writes bench/results/convergence_<adapter>.csv (every checkpoint), .json
(settings, versions, fits, validation) and .png.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from bench.common import (
    CHANNELS,
    RELATIVE_MSE_EPSILON,
    Run,
    add_max_spp,
    agreement,
    argument_parser,
    checkpoints,
    curves,
    errors,
    figure,
    fit_power_law,
    image_failures,
    log,
    parse,
    save_figure,
    seconds_to_reach,
    sidak_critical_z,
    write_csv,
    write_result,
)
from wgputrace import Renderer, load_scene
from wgputrace.testing.references import load_reference

SCENES = ("cornell", "tiny_light")
INTEGRATORS = ("mis", "nee", "bsdf")
# Time-to-equal-error ratios are measured against this strategy's error at its last checkpoint.
BASELINE_INTEGRATOR = "bsdf"
VALIDATION_SPP = 16
VALIDATION_SIGNIFICANCE = 1e-3  # family-wise, over scenes x integrators x channels
CSV_COLUMNS = ("scene", "integrator", "run", "seed", "spp", "seconds", "cpu_seconds", "rmse", "relative_mse", "raw_mse")


def validate(renderer: Renderer, reference_mean: np.ndarray, z_critical: float) -> dict:
    """The first image (it compiles the shader): finite, nothing dropped, mean equal to the reference's."""
    renderer.render(VALIDATION_SPP)
    image = renderer.image()
    check = agreement(image, reference_mean.astype(np.float32), z_critical)
    renderer.reset()
    failures = image_failures(image, renderer.dropped_samples) + check["failures"]
    return {"spp": VALIDATION_SPP, "agreement_with_reference": check, "failures": failures}


def measure(scene: str, integrator: str, args: argparse.Namespace, z_critical: float) -> tuple[list[dict], dict]:
    reference = load_reference(scene)
    width, height, max_depth = (reference.metadata[key] for key in ("width", "height", "max_depth"))
    reference_mean, reference_variance = reference.estimate.mean, reference.estimate.variance
    rows, validation = [], None
    for run in range(args.runs):
        seed = args.seed + run
        renderer = Renderer(load_scene(scene), width, height, seed=seed, max_depth=max_depth, integrator=integrator)
        if validation is None:
            validation = validate(renderer, reference_mean, z_critical)
            if validation["failures"]:
                raise SystemExit(f"{scene}/{integrator}: validation failed, nothing timed: {validation['failures']}")
        else:
            renderer.render(1)  # this renderer's warm-up (a Mesa cache hit), discarded
            renderer.reset()
        cpu_seconds = 0.0
        for spp in checkpoints(args.max_spp):
            cpu_start = time.process_time()
            renderer.render(spp - renderer.samples_per_pixel)
            cpu_seconds += time.process_time() - cpu_start
            if renderer.dropped_samples:
                raise SystemExit(f"{scene}/{integrator} run {run + 1}: {renderer.dropped_samples} dropped samples")
            row = {"scene": scene, "integrator": integrator, "run": run + 1, "seed": seed, "spp": spp}
            row["seconds"], row["cpu_seconds"] = renderer.stats.render_seconds, cpu_seconds
            rows.append(row | errors(renderer.image(), reference_mean, reference_variance))
        log(
            f"{scene}/{integrator} run {run + 1}: {args.max_spp} spp in {row['seconds']:.1f} s, RMSE {rows[-1]['rmse']:.4g}"
        )
    settings = {"width": width, "height": height, "max_depth": max_depth, "reference": reference.metadata}
    return rows, {"validation": validation, **settings}


def time_to_equal_error(curves_by_name: dict) -> dict:
    """Per scene and integrator: the time it needs to reach the relative MSE that the baseline
    (BSDF sampling) reaches at its last checkpoint, over the baseline's time for it. Both times
    come from power laws fitted to relative MSE against time over the checkpoints from
    FIT_MIN_SPP on, so single noisy checkpoints (a firefly in a heavy-tailed estimator) do not
    decide the ratio. For unbiased strategies relative MSE falls as 1/time, so the ratio does not
    depend on which error level is chosen."""
    ratios = {}
    for baseline in (c for c in curves_by_name.values() if c["integrator"] == BASELINE_INTEGRATOR):
        base_slope, base_intercept = fit_power_law(baseline, "relative_mse")
        target = float(np.exp(base_intercept + base_slope * np.log(baseline["seconds"][-1])))
        for curve in (c for c in curves_by_name.values() if c["scene"] == baseline["scene"]):
            slope, intercept = fit_power_law(curve, "relative_mse")
            seconds = seconds_to_reach(slope, intercept, target)
            ratios[f"{curve['scene']}/{curve['integrator']}"] = {
                "baseline_relative_mse": target,
                "baseline_seconds": baseline["seconds"][-1],
                "seconds_to_reach_it": seconds,
                "ratio_to_baseline_time": seconds / baseline["seconds"][-1],
                "fitted_slope_relative_mse_vs_seconds": slope,
            }
    return ratios


def plot(path: Path, result: dict) -> None:
    chart = figure(11.0, 8.0)
    panels = chart.subplots(2, 2)
    colors = {"cornell": "#3b75af", "tiny_light": "#c4452c"}
    styles = {"mis": "-", "bsdf": ":"}
    metrics = (("rmse", "slope_rmse_vs_spp", "RMSE"), ("relative_mse", "slope_relative_mse_vs_spp", "relative MSE"))
    axes_keys = (("seconds", "render time (s, median over runs)"), ("spp", "samples per pixel"))
    for row, (metric, slope, metric_label) in enumerate(metrics):
        for column, (axis_key, axis_label) in enumerate(axes_keys):
            axes = panels[row][column]
            for curve in result["curves"].values():
                label = f"{curve['scene']}, {curve['integrator']}"
                axes.loglog(
                    curve[axis_key],
                    curve[metric],
                    styles.get(curve["integrator"], "--"),
                    marker="o",
                    markersize=3,
                    color=colors.get(curve["scene"], "black"),
                    label=f"{label} (slope {curve[slope]:.2f} vs spp)" if column == 1 else label,
                )
            axes.set_xlabel(axis_label)
            axes.set_ylabel(metric_label)
            axes.grid(which="both", alpha=0.3)
            axes.legend(fontsize=7)
    title = (
        f"wgputrace convergence against Mitsuba {result['mitsuba']} references, {result['width']}x{result['height']}, "
        f"up to {result['max_spp']} spp, {result['runs']} runs, max depth {result['max_depth']}"
    )
    save_figure(chart, path, result, title, fontsize=10)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, seed=1)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), help=f"default: {' '.join(SCENES)}")
    parser.add_argument("--integrators", nargs="+", default=list(INTEGRATORS), help=f"default: {' '.join(INTEGRATORS)}")
    add_max_spp(parser, 256)
    parser.add_argument("--runs", type=int, default=2, help="progressive renders per scene and integrator (default 2)")
    args = parse(parser, argv, "runs")
    run = Run()
    z_critical = sidak_critical_z(VALIDATION_SIGNIFICANCE, len(args.scenes) * len(args.integrators) * len(CHANNELS))
    rows, settings = [], {}
    for scene in args.scenes:
        for integrator in args.integrators:
            new_rows, settings[f"{scene}/{integrator}"] = measure(scene, integrator, args, z_critical)
            rows += new_rows
    first = next(iter(settings.values()))
    result = {
        "scene": list(args.scenes),
        "mitsuba": first["reference"]["mitsuba"],
        "width": first["width"],
        "height": first["height"],
        "max_depth": first["max_depth"],
        "spp": args.max_spp,  # the last checkpoint; the curves hold every one
        "max_spp": args.max_spp,
        "runs": args.runs,
        "seed": args.seed,
        "relative_mse_epsilon": RELATIVE_MSE_EPSILON,
        "timing": "wall clock of Renderer.render between checkpoints, summed; image read-backs not timed. "
        "cpu_seconds (CSV): process CPU time of the same calls, llvmpipe's threads included, which other load "
        "on a CPU adapter hardly changes",
        "error": "MSE against the reference minus the reference's per-pixel variance (its squared standard "
        "error plus float16 rounding), averaged over pixels and channels",
        "scenes": settings,
        "curves": curves(rows),
    }
    result["time_to_equal_error"] = time_to_equal_error(result["curves"])
    write_result("convergence", result, out=args.out, plot=plot, run=run)
    write_csv("convergence", rows, CSV_COLUMNS, args.out)
    for name, curve in result["curves"].items():
        print(
            f"{name:24s} RMSE {curve['rmse'][-1]:.4g} at {curve['spp'][-1]} spp in {curve['seconds'][-1]:.1f} s; "
            f"slope {curve['slope_rmse_vs_spp']:.3f} vs spp, {curve['slope_rmse_vs_seconds']:.3f} vs time; "
            f"relative MSE slope {curve['slope_relative_mse_vs_spp']:.3f}"
        )
    for name, ratio in result["time_to_equal_error"].items():
        print(
            f"{name:24s} reaches {BASELINE_INTEGRATOR}'s final relative MSE in {ratio['ratio_to_baseline_time']:.3g} "
            f"of its time (fitted slope {ratio['fitted_slope_relative_mse_vs_seconds']:.2f})"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
