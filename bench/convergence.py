"""Error against time on the Cornell box and the scenes that break path tracers: RMSE against the
Mitsuba 3 reference as a function of render time, for each integrator x sampler of ours and for
Mitsuba 3's `path` integrator with its `independent` and `multijitter` samplers, in one run.

    python -m bench.convergence          (Mitsuba's rows too where mitsuba imports: the `reference` extra)
    python -m bench.convergence --scenes caustic --integrators mis bdpt --runs 1
    python -m bench --only convergence

Each strategy is validated against the reference, then rendered `runs` times and read back at
checkpoints 1, 2, 4, ... spp (`measure_ours`, `measure_mitsuba`); a strategy the installed code
lacks is skipped, its reason recorded. `read_off` takes each curve's time to a common RMSE and its
efficiency from power laws fitted to RMSE against time, by wall-clock and by process CPU time,
which the suite judges the targets by: other work on shared cores swings wall-clock ratios.
Writes bench/results/convergence_<adapter>.csv, .json and .png.
"""

from __future__ import annotations

import argparse
import contextlib
import inspect
import json
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import add_max_spp, argument_parser, log, parse
from bench.error_curves import FIT_MIN_SPP, checkpoints, curves, error_at, errors, fit_power_law, seconds_to_reach
from bench.mitsuba import MitsubaSide, add_mitsuba_variant, mitsuba_missing, threads
from bench.provenance import Run
from bench.result_files import write_csv, write_result
from bench.validation import CHANNELS, agreement, image_failures, sidak_critical_z
from wgputrace import Renderer, Scene, load_scene
from wgputrace.scenes.caustic import caustic_mask
from wgputrace.testing.image_statistics import Estimate
from wgputrace.testing.references import Reference, load_reference

SCENES = ("cornell", "door_ajar", "caustic", "glossy_through_glossy", "tiny_light")
INTEGRATORS = ("mis", "nee", "bsdf", "bdpt")
SAMPLERS = ("independent", "sobol")
MITSUBA = "mitsuba"
MITSUBA_SAMPLERS = ("independent", "multijitter")
# Pixels where one kind of light transport decides the error, measured apart as "<scene>:<region>".
LAMP = "lamp"


def caustic_pixels(scene: Scene, width: int, height: int) -> np.ndarray:
    return caustic_mask(scene.camera, width, height)


def away_from_lamp(scene: Scene, width: int, height: int) -> np.ndarray:
    """(height, width) bool: pixels at least one pixel away from the box the lamp's corners
    project to. tiny_light's lamp is sub-pixel and some 10^4 times brighter than the rest: the few
    pixels that see it carry nearly all of the whole image's squared error."""
    right, up, forward = scene.camera.image_plane(width, height)
    (lamp,) = [shape.world_vertices for shape in scene.shapes if shape.name == LAMP]
    offsets = lamp.reshape(-1, 3).astype(np.float64) - np.asarray(scene.camera.position)
    depth = offsets @ forward
    # camera_ray: forward + x right - y up over x, y in [-1, 1], row 0 at the top
    columns = ((offsets @ right) / (right @ right) / depth + 1.0) / 2.0 * width
    rows = ((offsets @ up) / (up @ up) / depth * -1.0 + 1.0) / 2.0 * height
    keep = np.ones((height, width), bool)
    keep[max(int(rows.min()) - 1, 0) : int(rows.max()) + 2, max(int(columns.min()) - 1, 0) : int(columns.max()) + 2] = (
        False
    )
    return keep


# Measured apart as "<scene>:<region>": the floor pixels the caustic falls on decide how well a
# strategy renders caustics, and tiny_light's lamp pixels otherwise decide its whole image's error.
REGIONS: dict[str, dict[str, Callable[[Scene, int, int], np.ndarray]]] = {
    "caustic": {"caustic_pixels": caustic_pixels},
    "tiny_light": {"away_from_lamp": away_from_lamp},
}
# References larger than the tests' (the Cornell box at 256x256, the issue's setting), made with
#   PYTHONPATH=scripts python -c "import make_references as m; from pathlib import Path; m.WIDTH = m.HEIGHT = 256; \
#       m.make_reference('cornell', m.ReferenceSettings(9, 128, 16), 'llvm_ad_rgb', Path('bench/references'))"
BENCH_REFERENCES = Path(__file__).resolve().parent / "references"
# --max-spp counts samples per pixel at this size; larger references stop at as many paths.
BASE_PIXELS = 128 * 128
# Issue 18's targets: ours as shipped reaches the Cornell box's fixed RMSE no later than Mitsuba
# (its default sampler), and bidirectional paths are this many times as efficient as mis.
TARGETS = {
    "cornell_time_over_mitsuba": 1.0,
    "bdpt_efficiency_over_mis": {"door_ajar": 5.0, "caustic:caustic_pixels": 10.0},
}
VALIDATION_SPP = 16
VALIDATION_SIGNIFICANCE = 1e-3  # family-wise, over scenes x strategies x channels
CSV_COLUMNS = ("scene", "integrator", "run", "seed", "spp", "seconds", "cpu_seconds", "rmse", "relative_mse", "raw_mse")


class Unavailable(Exception):
    """The installed code lacks a strategy (an integrator or sampler still to come, or Mitsuba)."""


class ValidationFailed(Exception):
    """A strategy's first image failed its checks: it is not timed."""


@dataclass(frozen=True)
class Strategy:
    """One curve's estimator: ours (an integrator with a sampler, and shader overrides under a
    `variant` name) or Mitsuba's path tracer with a sampler."""

    integrator: str  # ours: Renderer's integrator; Mitsuba: MITSUBA
    sampler: str
    variant: str = ""
    overrides: tuple[tuple[str, float], ...] = ()

    @property
    def label(self) -> str:
        """ "mis/sobol", "restir-ris/sobol", "mitsuba/multijitter": the curves' "integrator" column."""
        variant = f"-{self.variant}" if self.variant else ""
        return f"{self.integrator}{variant}/{self.sampler}"


def default_strategy() -> Strategy:
    """Ours as a user gets it: Renderer's default integrator and sampler."""
    parameters = inspect.signature(Renderer).parameters
    sampler = parameters["sampler"].default if "sampler" in parameters else "independent"
    return Strategy(parameters["integrator"].default, sampler)


BASELINE = default_strategy()
MITSUBA_BASELINE = Strategy(MITSUBA, "independent")


def renderer_options(strategy: Strategy) -> dict:
    """Renderer's keyword arguments for `strategy`; a Renderer without `sampler` has the independent one only."""
    overrides = {"shader_overrides": dict(strategy.overrides)} if strategy.overrides else {}
    if "sampler" in inspect.signature(Renderer).parameters:
        return {"integrator": strategy.integrator, "sampler": strategy.sampler, **overrides}
    if strategy.sampler != "independent":
        raise ValueError(
            f"this Renderer has no sampler option (only the independent sampler), got {strategy.sampler!r}"
        )
    return {"integrator": strategy.integrator}


def bench_reference(scene: str) -> Reference:
    """BENCH_REFERENCES' <scene>.npz where there is one, else the test's (`load_reference`)."""
    path = BENCH_REFERENCES / f"{scene}.npz"
    if not path.exists():
        return load_reference(scene)
    with np.load(path) as data:
        metadata = json.loads(str(data["metadata"]))
        mean = data["mean"].astype(np.float64)
        standard_error = data["standard_error"].astype(np.float64)
    return Reference(Estimate(mean, standard_error**2, metadata["passes"] - 1.0), metadata)


def scene_spp(max_spp: int, width: int, height: int) -> int:
    """The last checkpoint at this size: as many paths as `max_spp` at 128x128, a power of two,
    leaving checkpoints to fit."""
    spp = max_spp * BASE_PIXELS // (width * height)
    return max(1 << max(spp, 1).bit_length() - 1, FIT_MIN_SPP * 4)


@dataclass
class SceneSetup:
    name: str
    reference: Reference
    max_spp: int
    regions: dict[str, np.ndarray]  # region name: (height, width) bool mask

    @property
    def size(self) -> tuple[int, int]:
        return self.reference.metadata["width"], self.reference.metadata["height"]

    @property
    def max_depth(self) -> int:
        return self.reference.metadata["max_depth"]


def scene_setup(name: str, max_spp: int, regions_by_scene: dict = REGIONS) -> SceneSetup:
    reference = bench_reference(name)
    width, height = reference.metadata["width"], reference.metadata["height"]
    scene = load_scene(name)
    regions = {region: mask(scene, width, height) for region, mask in regions_by_scene.get(name, {}).items()}
    return SceneSetup(name, reference, scene_spp(max_spp, width, height), regions)


def error_rows(setup: SceneSetup, image: np.ndarray, row: dict) -> list[dict]:
    """`row` with the errors of `image`, on the whole image and on each of the scene's regions."""
    mean, variance = setup.reference.estimate.mean, setup.reference.estimate.variance
    rows = [row | {"scene": setup.name} | errors(image, mean, variance)]
    for region, mask in setup.regions.items():
        rows.append(row | {"scene": f"{setup.name}:{region}"} | errors(image[mask], mean[mask], variance[mask]))
    return rows


def validation(image: np.ndarray, dropped: int, setup: SceneSetup, z_critical: float) -> dict:
    check = agreement(image, setup.reference.estimate.mean.astype(np.float32), z_critical)
    return {
        "spp": VALIDATION_SPP,
        "agreement_with_reference": check,
        "failures": image_failures(image, dropped) + check["failures"],
    }


def new_renderer(setup: SceneSetup, strategy: Strategy, seed: int) -> Renderer:
    """Ours for `strategy`, or Unavailable where the installed Renderer refuses its integrator or
    sampler (checked before anything compiles)."""
    width, height = setup.size
    try:
        options = renderer_options(strategy)
        return Renderer(load_scene(setup.name), width, height, seed=seed, max_depth=setup.max_depth, **options)
    except (ValueError, TypeError) as error:
        raise Unavailable(str(error)) from None


def measure_ours(
    setup: SceneSetup, strategy: Strategy, args: argparse.Namespace, z_critical: float
) -> tuple[list[dict], dict]:
    """Progressive renders of `runs` seeds, read back at every checkpoint; only Renderer.render is
    timed. The first render validates (finite, nothing dropped, image mean equal to the
    reference's by a z-test) and, compiling the shader, is the warm-up."""
    rows, checked = [], None
    for run in range(args.runs):
        seed = args.seed + run
        renderer = new_renderer(setup, strategy, seed)
        if checked is None:
            renderer.render(VALIDATION_SPP)  # compiles the shader: the warm-up
            checked = validation(renderer.image(), renderer.dropped_samples, setup, z_critical)
            if checked["failures"]:
                raise ValidationFailed("; ".join(checked["failures"]))
        else:
            renderer.render(1)  # this renderer's warm-up (a Mesa cache hit), discarded
        renderer.reset()
        cpu_seconds = 0.0
        for spp in checkpoints(setup.max_spp):
            cpu_start = time.process_time()
            renderer.render(spp - renderer.samples_per_pixel)
            cpu_seconds += time.process_time() - cpu_start
            if renderer.dropped_samples:
                raise SystemExit(
                    f"{setup.name}/{strategy.label} run {run + 1}: {renderer.dropped_samples} dropped samples"
                )
            row = {"integrator": strategy.label, "run": run + 1, "seed": seed, "spp": spp}
            row |= {"seconds": renderer.stats.render_seconds, "cpu_seconds": cpu_seconds}
            rows += error_rows(setup, renderer.image(), row)
        log(
            f"{setup.name}/{strategy.label} run {run + 1}: {spp} spp in {row['seconds']:.1f} s, RMSE {rows[-1]['rmse']:.4g}"
        )
    return rows, {"validation": checked}


@contextlib.contextmanager
def mitsuba_sampler(mi, sampler: str):
    """Scenes that mitsuba_scene loads meanwhile get `sampler` as their sensor's sampler
    (mitsuba_scene itself always asks for `independent`)."""
    load_dict = mi.load_dict

    def with_sampler(description: dict, *rest, **options):
        if "sensor" in description:
            description = {**description, "sensor": {**description["sensor"], "sampler": {"type": sampler}}}
        return load_dict(description, *rest, **options)

    mi.load_dict = with_sampler
    try:
        yield
    finally:
        mi.load_dict = load_dict


def measure_mitsuba(
    mitsuba: tuple, setup: SceneSetup, strategy: Strategy, args: argparse.Namespace, z_critical: float
) -> tuple[list[dict], dict]:
    """Each checkpoint a fresh Mitsuba render at that spp (its usual use and its fastest), timed with
    evaluation, `runs` times; the first render validates and compiles."""
    if isinstance(mitsuba, str):
        raise Unavailable(mitsuba)
    mi, dr = mitsuba
    width, height = setup.size
    side = MitsubaSide(mi, dr, setup.name)
    with mitsuba_sampler(mi, strategy.sampler):
        side.scene(width, setup.max_depth)
    image = side.render(width, setup.max_depth, VALIDATION_SPP)[0]
    checked = validation(image, 0, setup, z_critical)
    if checked["failures"]:
        raise ValidationFailed("; ".join(checked["failures"]))
    for spp in checkpoints(setup.max_spp):  # every spp's kernel is the same; this proves it
        side.render(width, setup.max_depth, spp)
    side.kernel_report()
    rows = []
    for run in range(args.runs):
        for spp in checkpoints(setup.max_spp):
            image, wall, cpu = side.render(width, setup.max_depth, spp)
            if image_failures(image, 0):
                raise SystemExit(f"{setup.name}/{strategy.label} run {run + 1}, {spp} spp: {image_failures(image, 0)}")
            row = {
                "integrator": strategy.label,
                "run": run + 1,
                "seed": None,
                "spp": spp,
                "seconds": wall,
                "cpu_seconds": cpu,
            }
            rows += error_rows(setup, image, row)
        log(f"{setup.name}/{strategy.label} run {run + 1}: {spp} spp in {wall:.2f} s, RMSE {rows[-1]['rmse']:.4g}")
    return rows, {"validation": checked, "timed_kernels": side.compiled_nothing("timed renders")}


def load_mitsuba_pair(variant: str):
    """(mitsuba, drjit) with `variant` set."""
    import drjit

    from wgputrace.reference.mitsuba_scene import load_mitsuba

    return load_mitsuba(variant), drjit


def fitted_rmse(curve: dict, seconds: float) -> float:
    return error_at(*fit_power_law(curve, "rmse"), seconds)


def read_off(curves_by_name: dict) -> dict:
    """Per scene: the fixed RMSE (what ours as shipped reaches at its last checkpoint, by its fit;
    the largest fitted final RMSE where it did not run), each curve's time to reach it and its
    efficiency 1 / (MSE x seconds) at its last checkpoint, and both as ratios to BASELINE and
    MITSUBA_BASELINE where those ran. A time read outside the curve's fitted checkpoints is the
    power law carried on, flagged "extrapolated"; a curve whose fitted RMSE does not fall with
    time has no time to reach (None). For an unbiased strategy RMSE falls as time^-1/2, so time
    ratios at a common RMSE are inverse efficiency ratios."""
    table = {}
    for scene in dict.fromkeys(curve["scene"] for curve in curves_by_name.values()):
        mine = {c["integrator"]: c for c in curves_by_name.values() if c["scene"] == scene}
        final = {label: fitted_rmse(c, c["seconds"][-1]) for label, c in mine.items()}
        level = final.get(BASELINE.label, max(final.values()))
        entries = {}
        for label, curve in mine.items():
            slope, intercept = fit_power_law(curve, "rmse")
            reached = seconds_to_reach(slope, intercept, level) if slope < 0 else None
            fitted = [
                seconds for seconds, spp in zip(curve["seconds"], curve["spp"], strict=True) if spp >= FIT_MIN_SPP
            ]
            entries[label] = {
                "final_rmse": curve["rmse"][-1],
                "final_seconds": curve["seconds"][-1],
                "final_spp": curve["spp"][-1],
                "fitted_slope_rmse_vs_seconds": slope,
                "seconds_to_fixed_rmse": reached,
                "extrapolated": reached is not None and not fitted[0] <= reached <= fitted[-1],
                # measured, not fitted: one bright path moves a fit's slope (tiny_light) far more than its end
                "efficiency": 1.0 / (curve["rmse"][-1] ** 2 * curve["seconds"][-1]) if curve["rmse"][-1] > 0 else None,
            }
        for baseline in (BASELINE.label, MITSUBA_BASELINE.label):
            for label, entry in entries.items():
                entry[f"efficiency_over_{baseline}"] = ratio(entries, label, baseline)
                entry[f"time_over_{baseline}"] = ratio(entries, label, baseline, "seconds_to_fixed_rmse")
        table[scene] = {"fixed_rmse": level, "strategies": entries}
    return table


def ratio(entries: dict, numerator: str, denominator: str, key: str = "efficiency") -> float | None:
    """entries[numerator][key] / entries[denominator][key], None where either is missing."""
    a, b = entries.get(numerator, {}).get(key), entries.get(denominator, {}).get(key)
    return a / b if a is not None and b else None


def gains(table: dict) -> dict:
    """The issue's ratios per scene: each sampler's efficiency over the independent one (same
    integrator), bdpt's over mis (same sampler), and ours as shipped against Mitsuba's samplers
    (time to the fixed RMSE, ours over theirs)."""
    result = {}
    for scene, entry in table.items():
        entries = entry["strategies"]
        found = [Strategy(*label.split("/")) for label in entries]
        result[scene] = {
            "sampler_efficiency_over_independent": {
                s.label: ratio(entries, s.label, Strategy(s.integrator, "independent").label)
                for s in found
                if s.integrator != MITSUBA and s.sampler != "independent"
            },
            "bdpt_efficiency_over_mis": {
                s.sampler: ratio(entries, s.label, Strategy("mis", s.sampler).label)
                for s in found
                if s.integrator == "bdpt"
            },
            "ours_time_over_mitsuba": {
                sampler: ratio(entries, BASELINE.label, Strategy(MITSUBA, sampler).label, "seconds_to_fixed_rmse")
                for sampler in MITSUBA_SAMPLERS
            },
        }
    return result


INTEGRATOR_COLORS = {"mis": "#3b75af", "nee": "#519e3e", "bsdf": "#8c8c8c", "bdpt": "#c4452c", MITSUBA: "#000000"}
SAMPLER_STYLES = {"independent": "-", "sobol": "--", "multijitter": ":"}


def plot(path: Path, result: dict) -> None:
    scenes = list(result["table"])
    columns = 3
    rows = -(-(len(scenes) + 1) // columns)
    chart = figure(5.0 * columns, 4.0 * rows)
    panels = chart.subplots(rows, columns, squeeze=False).ravel()
    for axes, scene in zip(panels, scenes, strict=False):
        level = result["table"][scene]["fixed_rmse"]
        for curve in (c for c in result["curves"].values() if c["scene"] == scene):
            integrator, sampler = curve["integrator"].split("/")
            color = INTEGRATOR_COLORS.get(integrator, "#7a4ca0")
            axes.loglog(
                curve["seconds"],
                curve["rmse"],
                SAMPLER_STYLES.get(sampler, "-."),
                marker="o",
                markersize=2.5,
                color=color,
                label=curve["integrator"],
            )
            entry = result["table"][scene]["strategies"][curve["integrator"]]
            if entry["seconds_to_fixed_rmse"] is not None and not entry["extrapolated"]:
                axes.plot([entry["seconds_to_fixed_rmse"]], [level], "x", color=color, markersize=7)
        axes.axhline(level, color="grey", linewidth=0.8, linestyle="--")
        axes.set_title(f"{scene} (fixed RMSE {level:.3g}; x: read off inside a curve)", fontsize=9)
        axes.set_xlabel("render time (s)")
        axes.set_ylabel("RMSE against the reference")
        axes.grid(which="both", alpha=0.3)
        axes.legend(fontsize=6)
    bars = panels[len(scenes)]
    labels = sorted({label for entry in result["table"].values() for label in entry["strategies"]})
    width = 0.8 / max(len(labels), 1)
    for index, label in enumerate(labels):
        integrator, sampler = label.split("/")
        values = [
            result["table"][s]["strategies"].get(label, {}).get(f"efficiency_over_{BASELINE.label}") for s in scenes
        ]
        positions = [i + index * width for i, value in enumerate(values) if value]
        bars.bar(
            positions,
            [value for value in values if value],
            width,
            color=INTEGRATOR_COLORS.get(integrator, "#7a4ca0"),
            hatch={"sobol": "//", "multijitter": ".."}.get(sampler),
            edgecolor="white",
            label=label,
        )
    bars.set_yscale("log")
    bars.set_xticks([i + 0.4 - width / 2 for i in range(len(scenes))], scenes, rotation=30, fontsize=7, ha="right")
    bars.set_ylabel(f"efficiency 1/(MSE x s) over {BASELINE.label}")
    bars.axhline(1.0, color="grey", linewidth=0.8)
    bars.legend(fontsize=6)
    for axes in panels[len(scenes) + 1 :]:
        axes.set_visible(False)
    mitsuba = (
        f"{result['mitsuba_version']} {result.get('mitsuba_variant') or ''}"
        if result["mitsuba_version"]
        else "(not run)"
    )
    title = f"RMSE against time, ours and Mitsuba {mitsuba}, {result['runs']} run(s) per curve"
    save_figure(chart, path, result, title, fontsize=10)


def settings(args: argparse.Namespace) -> dict:
    """The settings every result names (SETTINGS_KEYS and the runs): sizes, spp and depths differ
    between scenes, so they are given per scene under "scenes"."""
    return {
        "scene": list(args.scenes),
        "width": None,  # per scene: "scenes"
        "height": None,
        "spp": args.max_spp,  # at 128x128; per scene: "scenes"
        "max_depth": None,
        "max_spp": args.max_spp,
        "runs": args.runs,
        "seed": args.seed,
    }


def strategies(args: argparse.Namespace) -> list[Strategy]:
    ours = [Strategy(integrator, sampler) for integrator in args.integrators for sampler in args.samplers]
    return ours + [Strategy(MITSUBA, sampler) for sampler in args.mitsuba_samplers]


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, seed=1)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), help=f"default: {' '.join(SCENES)}")
    parser.add_argument("--integrators", nargs="+", default=list(INTEGRATORS), help=f"default: {' '.join(INTEGRATORS)}")
    parser.add_argument("--samplers", nargs="+", default=list(SAMPLERS), help=f"default: {' '.join(SAMPLERS)}")
    parser.add_argument(
        "--mitsuba-samplers",
        nargs="*",
        default=list(MITSUBA_SAMPLERS),
        help=f"default: {' '.join(MITSUBA_SAMPLERS)}; none: no Mitsuba",
    )
    add_max_spp(parser, 256)
    add_mitsuba_variant(parser)
    parser.add_argument(
        "--runs", type=int, default=1, help="renders per scene and strategy, errors averaged (default 1)"
    )
    args = parse(parser, argv, "runs")
    run = Run()
    chosen = strategies(args)
    z_critical = sidak_critical_z(VALIDATION_SIGNIFICANCE, len(args.scenes) * len(chosen) * len(CHANNELS))
    # (mitsuba, drjit), or why Mitsuba cannot run here
    mitsuba = (
        (mitsuba_missing(args.mitsuba_variant) or load_mitsuba_pair(args.mitsuba_variant))
        if args.mitsuba_samplers
        else "no --mitsuba-samplers"
    )
    rows, scenes, skipped, failed = [], {}, {}, {}
    for name in args.scenes:
        setup = scene_setup(name, args.max_spp)
        width, height = setup.size
        scenes[name] = {
            "width": width,
            "height": height,
            "max_depth": setup.max_depth,
            "max_spp": setup.max_spp,
            "reference": setup.reference.metadata,
            "regions": {r: int(m.sum()) for r, m in setup.regions.items()},
            "strategies": {},
        }
        for strategy in chosen:
            try:
                if strategy.integrator == MITSUBA:
                    new_rows, record = measure_mitsuba(mitsuba, setup, strategy, args, z_critical)
                else:
                    new_rows, record = measure_ours(setup, strategy, args, z_critical)
            except Unavailable as why:
                skipped[f"{name}/{strategy.label}"] = str(why)
                log(f"{name}/{strategy.label} skipped: {why}")
                continue
            except ValidationFailed as why:
                failed[f"{name}/{strategy.label}"] = str(why)
                log(f"{name}/{strategy.label}: validation failed, not timed: {why}")
                continue
            rows += new_rows
            scenes[name]["strategies"][strategy.label] = record
    all_curves = curves(rows)
    table = read_off(all_curves)
    # the same by process CPU time (both renderers' worker threads run in this process), which the
    # other work on shared cores moves far less than wall time
    table_cpu = read_off(curves([row | {"seconds": row["cpu_seconds"]} for row in rows]))
    result = {
        **settings(args),
        "mitsuba_version": None if isinstance(mitsuba, str) else mitsuba[0].__version__,
        "mitsuba_variant": None if isinstance(mitsuba, str) else args.mitsuba_variant,
        "threads": None if isinstance(mitsuba, str) else threads(mitsuba[1]),
        "default_strategy": BASELINE.label,
        "targets": TARGETS,
        "timing": "ours: Renderer.render summed over the progressive checkpoints; Mitsuba: one fresh render per "
        "checkpoint at that spp, evaluated (multijitter rounds the count up to a product of two near factors: "
        "32 to 35, 128 to 132; the time is that of the samples it took); image read-backs not timed. "
        "cpu_seconds (CSV): process CPU time",
        "error": "MSE against the reference minus the reference's per-pixel variance, over pixels and channels "
        "(on a region's pixels for '<scene>:<region>')",
        "read_off": "power law fitted to RMSE against seconds from FIT_MIN_SPP on: time to the scene's fixed RMSE "
        "(ours as shipped at its last checkpoint, fitted) and efficiency 1/(MSE x seconds) at the last checkpoint",
        "skipped": skipped,
        "validation_failed": failed,
        "scenes": scenes,
        "curves": all_curves,
        "table": table,
        "gains": gains(table),
        "table_process_cpu": table_cpu,
        "gains_process_cpu": gains(table_cpu),
    }
    write_result("convergence", result, out=args.out, plot=plot, run=run)
    write_csv("convergence", rows, CSV_COLUMNS, args.out)
    print(summary(result))
    return 0


def summary(result: dict) -> str:
    lines = [
        f"{'scene':34s} {'strategy':20s} {'RMSE':>9s} {'s':>7s} {'slope':>6s} {'t@fixed':>8s} {'eff/' + BASELINE.label:>22s}"
    ]
    for scene, entry in result["table"].items():
        for label, row in entry["strategies"].items():
            reached = row["seconds_to_fixed_rmse"]
            over = row[f"efficiency_over_{BASELINE.label}"]
            lines.append(
                f"{scene:34s} {label:20s} {row['final_rmse']:9.4g} {row['final_seconds']:7.2f} "
                f"{row['fitted_slope_rmse_vs_seconds']:6.2f} {'-' if reached is None else f'{reached:.2f}':>8s} "
                f"{'-' if over is None else f'{over:.3g}':>22s}"
            )
    lines += [f"skipped {name}: {reason}" for name, reason in result["skipped"].items()]
    lines += [f"VALIDATION FAILED {name}: {reason}" for name, reason in result["validation_failed"].items()]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
