"""Error against time: RMSE and relative MSE of our image against the Mitsuba 3 reference, as
functions of samples per pixel and of render time, for the Cornell box and the tiny-light scene.

    python bench/convergence.py                 (or: python -m bench.convergence)
    python bench/convergence.py --max-spp 64 --runs 1 --integrators mis

For each scene and integrator: a validation render first (finite, no dropped samples, image mean
equal to the reference's within a z-test; its first dispatch is the shader compile, so it is the
warm-up too), then `runs` progressive renders from different seeds, the image read back at 1, 2,
4, ... max-spp samples per pixel. Only Renderer.render is timed; read-backs are not. The reference
(tests/references/<scene>.npz, 128x128) is noisy itself: since ours and it are independent,
E[(ours - reference)^2] = our MSE + the reference's variance, which is subtracted, so the curves
show our error alone. A converging unbiased estimator has RMSE ~ spp^-0.5 (slope -0.5 on log-log
axes) and relative MSE ~ spp^-1; the height of a curve is the efficiency later work improves.
Writes bench/results/convergence_<adapter>.csv (every checkpoint), .json (settings, versions,
fits, validation) and .png.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.common import RESULTS_DIR, load_average, result_stem, write_result  # noqa: E402
from bench.throughput import agreement, sidak_critical_z  # noqa: E402
from tests.render.reference_images import load_reference  # noqa: E402
from wgputrace import Renderer  # noqa: E402
from wgputrace.scenes import scene_by_name  # noqa: E402

SCENES = ("cornell", "tiny_light")
INTEGRATORS = ("mis", "nee", "bsdf")
# Time-to-equal-error ratios are measured against this strategy's error at its last checkpoint.
BASELINE_INTEGRATOR = "bsdf"
VALIDATION_SPP = 16
VALIDATION_SIGNIFICANCE = 1e-3  # family-wise, over scenes x integrators x channels
CHANNELS = 3
# relative MSE = mean((ours - reference)^2 / (reference^2 + this)): dark pixels do not dominate
RELATIVE_MSE_EPSILON = 1e-2
# Slopes are fitted from this many samples per pixel on: the first few checkpoints are dominated
# by the odd first sample and by what a single image happens to hit.
FIT_MIN_SPP = 4
CSV_COLUMNS = ("scene", "integrator", "run", "seed", "spp", "seconds", "cpu_seconds", "rmse", "relative_mse", "raw_mse")


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def errors(image: np.ndarray, reference_mean: np.ndarray, reference_variance: np.ndarray) -> dict:
    """Our MSE and relative MSE with the reference's own variance taken out, and the raw MSE."""
    squared = (image.astype(np.float64) - reference_mean) ** 2
    mse = float(np.mean(squared - reference_variance))
    relative = float(np.mean((squared - reference_variance) / (reference_mean**2 + RELATIVE_MSE_EPSILON)))
    return {"rmse": float(np.sqrt(max(mse, 0.0))), "relative_mse": relative, "raw_mse": float(np.mean(squared))}


def fit_slope(x: list[float], y: list[float]) -> float:
    """Least-squares slope of log y against log x (positive values only)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    keep = (x > 0) & (y > 0)
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def checkpoints(max_spp: int) -> list[int]:
    spp, points = 1, []
    while spp <= max_spp:
        points.append(spp)
        spp *= 2
    return points


def validate(renderer: Renderer, reference_mean: np.ndarray, z_critical: float) -> dict:
    """The first image (it compiles the shader): finite, nothing dropped, mean equal to the reference's."""
    renderer.render(VALIDATION_SPP)
    image = renderer.image()
    failures = []
    if not np.isfinite(image).all():
        failures.append(f"{np.count_nonzero(~np.isfinite(image))} image values are NaN or infinite")
    if renderer.dropped_samples:
        failures.append(f"the shader dropped {renderer.dropped_samples} samples (non-finite or cut short)")
    check = agreement(image, reference_mean.astype(np.float32), z_critical)
    failures += check["failures"]
    renderer.reset()
    return {"spp": VALIDATION_SPP, "agreement_with_reference": check, "failures": failures}


def measure(scene: str, integrator: str, args: argparse.Namespace, z_critical: float) -> tuple[list[dict], dict]:
    reference = load_reference(scene)
    width, height, max_depth = (reference.metadata[key] for key in ("width", "height", "max_depth"))
    reference_mean, reference_variance = reference.estimate.mean, reference.estimate.variance
    rows, validation = [], None
    for run in range(args.runs):
        seed = args.seed + run
        renderer = Renderer(scene_by_name(scene), width, height, seed=seed, max_depth=max_depth, integrator=integrator)
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
            image = renderer.image()
            if renderer.dropped_samples:
                raise SystemExit(
                    f"{scene}/{integrator} run {run + 1}: {renderer.dropped_samples} dropped samples (non-finite or cut short)"
                )
            row = {"scene": scene, "integrator": integrator, "run": run + 1, "seed": seed, "spp": spp}
            row["seconds"], row["cpu_seconds"] = renderer.stats.render_seconds, cpu_seconds
            rows.append(row | errors(image, reference_mean, reference_variance))
        _log(
            f"{scene}/{integrator} run {run + 1}: {args.max_spp} spp in {renderer.stats.render_seconds:.1f} s, RMSE {rows[-1]['rmse']:.4g}"
        )
    settings = {"width": width, "height": height, "max_depth": max_depth, "reference": reference.metadata}
    return rows, {"validation": validation, **settings}


def curves(rows: list[dict]) -> dict:
    """Per scene and integrator: per checkpoint the MSEs averaged over runs, the median time, and slopes."""
    result = {}
    for key in dict.fromkeys((row["scene"], row["integrator"]) for row in rows):
        mine = [row for row in rows if (row["scene"], row["integrator"]) == key]
        spp = sorted({row["spp"] for row in mine})
        at = {s: [row for row in mine if row["spp"] == s] for s in spp}
        rmse = [float(np.sqrt(max(np.mean([r["rmse"] ** 2 for r in at[s]]), 0.0))) for s in spp]
        relative = [float(np.mean([r["relative_mse"] for r in at[s]])) for s in spp]
        seconds = [float(np.median([r["seconds"] for r in at[s]])) for s in spp]
        fit = [i for i, s in enumerate(spp) if s >= FIT_MIN_SPP]

        def pick(values, indices=fit):
            return [values[i] for i in indices]

        result[f"{key[0]}/{key[1]}"] = {
            "scene": key[0],
            "integrator": key[1],
            "spp": spp,
            "seconds": seconds,
            "rmse": rmse,
            "relative_mse": relative,
            "slope_rmse_vs_spp": fit_slope(pick(spp), pick(rmse)),
            "slope_rmse_vs_seconds": fit_slope(pick(seconds), pick(rmse)),
            "slope_relative_mse_vs_spp": fit_slope(pick(spp), pick(relative)),
            # efficiency: 1 / (relative MSE x seconds) at the last checkpoint
            "efficiency": 1.0 / (relative[-1] * seconds[-1]) if relative[-1] > 0 else None,
        }
    return result


def fit_power_law(curve: dict, metric: str) -> tuple[float, float]:
    """Slope and intercept of log `metric` against log seconds over the checkpoints from FIT_MIN_SPP on."""
    keep = [i for i, spp in enumerate(curve["spp"]) if spp >= FIT_MIN_SPP]
    log_seconds = np.log([curve["seconds"][i] for i in keep])
    log_error = np.log([max(curve[metric][i], np.finfo(float).tiny) for i in keep])
    slope, intercept = np.polyfit(log_seconds, log_error, 1)
    return float(slope), float(intercept)


def seconds_to_reach(slope: float, intercept: float, error: float) -> float:
    """Where the power law log error = intercept + slope log seconds reaches `error`."""
    return float(np.exp((np.log(error) - intercept) / slope))


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
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11.0, 8.0))
    FigureCanvasAgg(figure)
    panels = figure.subplots(2, 2)
    colors = {"cornell": "#3b75af", "tiny_light": "#c4452c"}
    styles = {"mis": "-", "bsdf": ":"}
    for curve in result["curves"].values():
        label = f"{curve['scene']}, {curve['integrator']}"
        for row, (metric, slope) in enumerate(
            (("rmse", "slope_rmse_vs_spp"), ("relative_mse", "slope_relative_mse_vs_spp"))
        ):
            for column, axis_key in enumerate(("seconds", "spp")):
                axes = panels[row][column]
                axes.loglog(
                    curve[axis_key],
                    curve[metric],
                    styles.get(curve["integrator"], "--"),
                    marker="o",
                    markersize=3,
                    color=colors.get(curve["scene"], "black"),
                    label=f"{label} (slope {curve[slope]:.2f} vs spp)" if column == 1 else label,
                )
    for column, axis_label in enumerate(("render time (s, median over runs)", "samples per pixel")):
        for row, metric_label in enumerate(("RMSE", f"relative MSE (eps {RELATIVE_MSE_EPSILON:g})")):
            axes = panels[row][column]
            axes.set_xlabel(axis_label)
            axes.set_ylabel(metric_label)
            axes.grid(which="both", alpha=0.3)
            axes.legend(fontsize=7)
    figure.suptitle(
        f"wgputrace convergence against Mitsuba {result['mitsuba']} references on {result['adapter']['adapter']} "
        f"({result['adapter']['backend']})\n{result['width']}x{result['height']}, up to {result['max_spp']} spp, "
        f"{result['runs']} runs, max depth {result['max_depth']}, rev {result['git_revision']}",
        fontsize=10,
    )
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def parse_arguments(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), help=f"default: {' '.join(SCENES)}")
    parser.add_argument("--integrators", nargs="+", default=list(INTEGRATORS), help=f"default: {' '.join(INTEGRATORS)}")
    parser.add_argument("--max-spp", type=int, default=256, help="last checkpoint, a power of two (default 256)")
    parser.add_argument("--runs", type=int, default=2, help="progressive renders per scene and integrator (default 2)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first run; run k uses seed + k")
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    args = parser.parse_args(argv)
    if args.max_spp < FIT_MIN_SPP * 4 or args.max_spp & (args.max_spp - 1):
        parser.error(f"--max-spp must be a power of two >= {FIT_MIN_SPP * 4}, got {args.max_spp}")
    if args.runs < 1:
        parser.error(f"--runs must be at least 1, got {args.runs}")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_arguments(argv)
    started = time.perf_counter()
    load_before = load_average()
    z_critical = sidak_critical_z(VALIDATION_SIGNIFICANCE, len(args.scenes) * len(args.integrators) * CHANNELS)
    rows, settings = [], {}
    for scene in args.scenes:
        for integrator in args.integrators:
            new_rows, settings[f"{scene}/{integrator}"] = measure(scene, integrator, args, z_critical)
            rows += new_rows
    first = next(iter(settings.values()))
    result = {
        "load_average_before_after": [load_before, load_average()],
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
        "fit_min_spp": FIT_MIN_SPP,
        "timing": "wall clock of Renderer.render between checkpoints, summed; image read-backs not timed. "
        "cpu_seconds (CSV): process CPU time of the same calls, llvmpipe's threads included, which other load "
        "on a CPU adapter hardly changes",
        "error": "MSE against the reference minus the reference's per-pixel variance (its squared standard "
        "error plus float16 rounding), averaged over pixels and channels",
        "scenes": settings,
        "curves": curves(rows),
        "wall_seconds": time.perf_counter() - started,
    }
    result["time_to_equal_error"] = time_to_equal_error(result["curves"])
    paths = write_result("convergence", result, out=args.out, plot=plot)
    csv_path = result_stem("convergence", args.out).with_suffix(".csv")
    lines = [",".join(CSV_COLUMNS)] + [",".join(str(row[column]) for column in CSV_COLUMNS) for row in rows]
    csv_path.write_text("\n".join(lines) + "\n")
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
    print(f"wrote {csv_path}, {paths['json'].name}, {paths['png'].name} in {result['wall_seconds']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
