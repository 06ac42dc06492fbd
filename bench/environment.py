"""Environment lighting (issue 15): what importance sampling a map gains over uniform sampling, what
the environment costs per sample, and whether a scene without the new lights runs as fast as before.

    python -m bench.environment
    python -m bench.environment --size 64 --reference-spp 1024 --cornell-rounds 5

On the sunny scene (a diffuse sphere on a plane under a generated sky map with a small, bright sun;
MIS): the efficiency 1 / (MSE x seconds) of the map importance sampled and sampled uniformly
(`efficiency`; issue 15's target 20x), and the cost per sample under the map, a constant and no
environment (`cost_per_sample`). Then the Cornell box against the commit before the lights work
(`cornell_against_baseline`; issue 15: within 3%), judged by process CPU time, which other work on
shared cores moves far less than wall time. Writes bench/results/environment_<adapter>.json and .png.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.error_curves import errors
from bench.provenance import REPO_ROOT, Run, worktree
from bench.result_files import write_result
from bench.timing import fresh_image
from bench.validation import agreement, image_failures, sidak_critical_z
from wgputrace import Camera, Diffuse, Environment, Renderer, Scene, make_icosphere, make_plane
from wgputrace.scene.lights.environment import local_of_uv

MAP_SIZE = (512, 256)
SUN_DIRECTION = (0.5, 0.6, -0.4)  # towards the sun: high, on the camera's side, from the picture's left
SUN_DIAMETER_DEGREES = 3.0
SUN_RADIANCE = 3000.0
HORIZON, ZENITH, GROUND = (0.9, 0.95, 1.0), (0.25, 0.45, 0.9), (0.12, 0.1, 0.08)
MAX_DEPTH = 9
# The shader override that samples the map uniformly over the sphere (pdf 1 / 4 pi), still weighted
# by MIS against BSDF sampling, as pbrt's UniformInfiniteLight.
UNIFORM_SAMPLING = "ENVIRONMENT_UNIFORM_SAMPLING"
METHODS = {"importance sampled": None, "uniform sphere": {UNIFORM_SAMPLING: 1}}
EFFICIENCY_TARGET = 20.0
# The reference is another renderer from this seed, independent of the timed renders' seed 1.
REFERENCE_SEED = 1000
VALIDATION_SIGNIFICANCE = 1e-3  # family-wise, over methods x channels
# The environment's cost: the sunny scene lit by each of these.
LIGHTINGS = ("map", "constant", "none")
CONSTANT_RADIANCE = 1.0
# Mean radiance of the pictures lit by a map and by a constant: a coarse gate, not an accuracy test.
SANE_BAND = (0.05, 20.0)
BASELINE_REVISION = "bdd5644"
CORNELL_TARGET = 1.03  # issue 15: as fast as before within 3%

# The program each checkout's process runs with `python -c` from the checkout's root, so that the
# checkout's wgputrace is imported; it uses only API both revisions have. It holds a Cornell box
# renderer (seed 1; its first render compiles) and answers each request line on stdin with a JSON
# line: "image SPP" renders SPP samples from the seed and gives the picture's hash, "time SPP"
# renders SPP new samples and gives their wall and process CPU seconds.
CORNELL_WORKER = """
import hashlib, inspect, json, sys, time
import numpy as np
import wgputrace
# checkouts from before the Sobol sampler had only the independent one: compare like with like
options = {"sampler": "independent"} if "sampler" in inspect.signature(wgputrace.Renderer).parameters else {}
renderer = wgputrace.Renderer(wgputrace.default_scene(), int(sys.argv[1]), int(sys.argv[2]), seed=1, **options)
renderer.render(1)
print(json.dumps({"module": wgputrace.__file__}), flush=True)
for line in sys.stdin:
    request, spp = line.split()
    if request == "image":
        renderer.restart()
        renderer.render(int(spp))
        image = renderer.image()
        reply = {"sha256": hashlib.sha256(image.tobytes()).hexdigest(), "mean": float(image.mean()),
                 "finite": bool(np.isfinite(image).all()), "dropped": renderer.dropped_samples}
    else:
        renderer.reset()
        renderer.context.finish()
        wall, cpu = time.perf_counter(), time.process_time()
        renderer.render(int(spp))
        reply = {"wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu}
    print(json.dumps(reply), flush=True)
"""


# -- the sunny scene ------------------------------------------------------------------------------


def sunny_map() -> np.ndarray:
    """Texels (H, W, 3): the sky's gradient by elevation, dark ground below the horizon, the sun a disc."""
    width, height = MAP_SIZE
    # where each texel sits in Mitsuba's convention (`local_of_uv`), and the way it looks
    u, v = np.meshgrid((np.arange(width) + 0.5) / width, np.arange(height) / (height - 1))
    directions = local_of_uv(np.stack([u, v], axis=-1).reshape(-1, 2)).reshape(height, width, 3)
    elevation = directions[..., 1:2]
    sky = np.asarray(HORIZON) + (np.asarray(ZENITH) - np.asarray(HORIZON)) * np.sqrt(np.clip(elevation, 0.0, 1.0))
    texels = np.where(elevation > 0.0, sky, np.asarray(GROUND))
    sun = np.asarray(SUN_DIRECTION) / np.linalg.norm(SUN_DIRECTION)
    texels[directions @ sun > np.cos(np.radians(SUN_DIAMETER_DEGREES / 2))] = SUN_RADIANCE
    return texels.astype(np.float32)


def sunny_scene(environment: Environment | None) -> Scene:
    sphere = make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 4, Diffuse("sphere", color=(0.7, 0.7, 0.7)), "sphere")
    ground = make_plane((0, -1, 0), (0, 0, 0), (40, 40), Diffuse("ground", color=(0.5, 0.5, 0.5)), "ground")
    scene = Scene([sphere, ground], Camera.looking_at((0, 1.2, -4.5), (0, -0.3, 0), vfov_degrees=45.0))
    scene.environment = environment
    return scene


def lit(lighting: str, texels: np.ndarray) -> Scene:
    """The sunny scene under the map, a constant environment, or none."""
    environments = {
        "map": lambda: Environment(texels=texels),
        "constant": lambda: Environment(radiance=CONSTANT_RADIANCE),
        "none": lambda: None,
    }
    return sunny_scene(environments[lighting]())


def mirrored_rounds(names: list[str], rounds: int, measure: Callable[[str], dict[str, float]]) -> dict[str, list]:
    """Per name, per round, the sums of what `measure(name)` returns (seconds by some clock) over
    the round's two measurements: each round measures every name twice in mirrored order (A B C C B
    A), so that load rising or falling steadily during a round weighs on each name alike."""
    sums = {name: [] for name in names}
    for _ in range(rounds):
        round_sums = {name: {} for name in names}
        for name in [*names, *reversed(names)]:
            for quantity, value in measure(name).items():
                round_sums[name][quantity] = round_sums[name].get(quantity, 0.0) + value
        for name in names:
            sums[name].append(round_sums[name])
    return sums


def round_ratios(runs: list[dict], baseline: list[dict], clock: str) -> list[float]:
    """Per round, run / baseline by `clock`: the ratios of work measured close together in time."""
    return [a[clock] / b[clock] for a, b in zip(runs, baseline, strict=True)]


# -- 1. importance sampling against uniform sampling ----------------------------------------------


def reference(texels: np.ndarray, size: int, spp: int, batches: int) -> tuple[np.ndarray, np.ndarray]:
    """The mean of `batches` importance-sampled images of spp / batches samples, and its variance per pixel."""
    renderer = Renderer(sunny_scene(Environment(texels=texels)), size, size, seed=REFERENCE_SEED, max_depth=MAX_DEPTH)
    images = []
    for batch in range(batches):
        image, dropped, _, _ = fresh_image(renderer, spp // batches)
        failures = image_failures(image, dropped, SANE_BAND)
        if failures:
            raise SystemExit(f"reference batch {batch}: {'; '.join(failures)}")
        images.append(image.astype(np.float64))
    stack = np.stack(images)
    return stack.mean(axis=0), stack.var(axis=0, ddof=1) / batches


def method_renderers(texels: np.ndarray, size: int) -> dict[str, Renderer]:
    scene = sunny_scene(Environment(texels=texels))
    return {
        name: Renderer(scene, size, size, seed=1, max_depth=MAX_DEPTH, shader_overrides=overrides)
        for name, overrides in METHODS.items()
    }


def validate_methods(renderers: dict[str, Renderer], reference_mean: np.ndarray, spp: int) -> dict:
    """Each method's picture from the seed: sane, with the reference's mean radiance; and the two differ."""
    z_critical = sidak_critical_z(VALIDATION_SIGNIFICANCE, len(renderers) * 3)
    checks, images = {}, {}
    for name, renderer in renderers.items():
        image, dropped, _, _ = fresh_image(renderer, spp, from_seed=True)
        test = agreement(image, reference_mean, z_critical)
        failures = image_failures(image, dropped, SANE_BAND) + test["failures"]
        if failures:
            raise SystemExit(f"{name} sampling, validation at {spp} spp: {'; '.join(failures)}")
        checks[name], images[name] = test, image
    first, second = images.values()
    if np.array_equal(first, second):
        raise SystemExit(f"uniform sampling drew the same picture as importance sampling: {UNIFORM_SAMPLING} ignored")
    return {"spp": spp, "z_critical": z_critical, "agreement": checks}


def efficiency(
    renderers: dict[str, Renderer], reference_mean: np.ndarray, reference_variance: np.ndarray, spp: int, repeats: int
) -> dict:
    """Per method: MSE per repeat, seconds per repeat, and 1 / (mean MSE x median seconds). The MSE
    is a mean, not a median: uniform sampling's error comes in rare bright samples."""
    runs = {name: {"mse": [], "relative_mse": [], "seconds": []} for name in renderers}
    for _ in range(repeats):
        for name, renderer in renderers.items():
            image, dropped, seconds, _ = fresh_image(renderer, spp)
            failures = image_failures(image, dropped)
            if failures:
                raise SystemExit(f"{name} sampling: {'; '.join(failures)}")
            error = errors(image, reference_mean, reference_variance)
            runs[name]["mse"].append(error["rmse"] ** 2)
            runs[name]["relative_mse"].append(error["relative_mse"])
            runs[name]["seconds"].append(seconds)
    result = {}
    for name, run in runs.items():
        mse, relative, seconds = np.mean(run["mse"]), np.mean(run["relative_mse"]), statistics.median(run["seconds"])
        result[name] = {
            **run,
            "mean_mse": float(mse),
            "mean_relative_mse": float(relative),
            "median_seconds": seconds,
            "efficiency": 1.0 / (mse * seconds),
            "relative_efficiency": 1.0 / (relative * seconds),
        }
    return result


# -- 2. the environment's cost per sample ---------------------------------------------------------


def cost_per_sample(texels: np.ndarray, size: int, spp: int, rounds: int) -> dict:
    """Seconds per sample (one path per pixel) under each lighting in mirrored rounds, and ratios to none."""
    renderers = {
        lighting: Renderer(lit(lighting, texels), size, size, seed=1, max_depth=MAX_DEPTH) for lighting in LIGHTINGS
    }
    for lighting, renderer in renderers.items():
        image, dropped, _, _ = fresh_image(renderer, spp)  # the warm-up compiles, and the picture to check
        failures = image_failures(image, dropped, None if lighting == "none" else SANE_BAND)
        if lighting == "none" and np.any(image):
            failures.append("a scene without light is not black")
        if failures:
            raise SystemExit(f"{lighting} environment: {'; '.join(failures)}")

    def measure(lighting: str) -> dict[str, float]:
        _, _, wall, cpu = fresh_image(renderers[lighting], spp)
        return {"wall": wall, "cpu": cpu}

    runs = mirrored_rounds(list(LIGHTINGS), rounds, measure)
    paths = 2 * spp * size * size  # a round renders each twice
    return {
        lighting: {
            "rounds": entries,
            "median_ns_per_path": statistics.median(entry["wall"] for entry in entries) / paths * 1e9,
            "over_none": statistics.median(round_ratios(entries, runs["none"], "wall")),
            "over_none_process_cpu": statistics.median(round_ratios(entries, runs["none"], "cpu")),
        }
        for lighting, entries in runs.items()
    }


# -- 3. the Cornell box against the commit before the lights --------------------------------------


class CornellWorker:
    """A process running CORNELL_WORKER in `checkout`; `ask` sends one request and reads its reply."""

    def __init__(self, checkout: Path, size: int) -> None:
        self.checkout = checkout
        self.process = subprocess.Popen(
            [sys.executable, "-c", CORNELL_WORKER, str(size), str(size)],
            cwd=checkout,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        self.module = Path(self.read()["module"])
        if not self.module.is_relative_to(checkout):
            raise SystemExit(f"the process in {checkout} imported {self.module}, not that checkout's wgputrace")

    def read(self) -> dict:
        line = self.process.stdout.readline()
        if not line:
            raise SystemExit(f"the Cornell box process in {self.checkout} ended (exit {self.process.wait()})")
        return json.loads(line)

    def ask(self, request: str, spp: int) -> dict:
        self.process.stdin.write(f"{request} {spp}\n")
        self.process.stdin.flush()
        return self.read()

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait()


def cornell_against_baseline(revision: str, size: int, spp: int, rounds: int) -> dict:
    """The Cornell box in one process per checkout (the baseline a git worktree of `revision`): both
    pictures equal bit for bit from the same seed, then `rounds` mirrored rounds time both; the
    medians of the per-round ratios current / baseline by process CPU time (llvmpipe's threads
    included) and by wall time."""
    with worktree(revision) as baseline:
        workers = {}
        try:
            workers["current"] = CornellWorker(REPO_ROOT, size)
            workers[f"baseline {revision}"] = CornellWorker(baseline, size)
            pictures = {name: worker.ask("image", spp) for name, worker in workers.items()}
            for name, picture in pictures.items():
                if not picture["finite"] or picture["dropped"]:
                    raise SystemExit(f"Cornell box, {name}: picture not finite or {picture['dropped']} samples dropped")
            if len({picture["sha256"] for picture in pictures.values()}) != 1:
                raise SystemExit(f"Cornell box: the checkouts' pictures differ from the same seed: {pictures}")
            for worker in workers.values():
                worker.ask("time", spp)  # discarded: the first timed render after the picture runs slower
            runs = mirrored_rounds(list(workers), rounds, lambda name: workers[name].ask("time", spp))
        finally:
            for worker in workers.values():
                worker.close()
    current, old = (runs[name] for name in workers)
    # by the clock on the wall and by the processes' CPU time
    ratios = {clock: round_ratios(current, old, key) for clock, key in (("wall", "wall"), ("process_cpu", "cpu"))}
    return {
        "baseline_revision": revision,
        # relative to each process's own checkout (CornellWorker refuses another's): no folder of this machine
        "modules": {name: worker.module.relative_to(worker.checkout).as_posix() for name, worker in workers.items()},
        "picture": next(iter(pictures.values())),
        "runs": runs,
        "median_seconds": {name: statistics.median(run["wall"] for run in entries) for name, entries in runs.items()},
        **{f"round_ratios_{clock}": ratios[clock] for clock in ratios},
        **{f"ratio_{clock}": statistics.median(ratios[clock]) for clock in ratios},
        "target": CORNELL_TARGET,
    }


# -- result ---------------------------------------------------------------------------------------


def plot(path: Path, result: dict) -> None:
    chart = figure(13.0, 4.0)
    methods = result["efficiency"]
    axis = chart.add_subplot(1, 3, 1)
    axis.bar(list(methods), [entry["efficiency"] for entry in methods.values()], color=["tab:blue", "tab:orange"])
    axis.set_yscale("log")
    axis.set_ylabel("1 / (MSE x seconds)")
    axis.set_title(f"importance sampling x{result['efficiency_ratio']:.0f} (target {EFFICIENCY_TARGET:g})")
    costs = result["cost_per_sample"]
    axis = chart.add_subplot(1, 3, 2)
    axis.bar(list(costs), [entry["median_ns_per_path"] for entry in costs.values()], color="tab:green")
    axis.set_ylabel("ns per path (sample per pixel)")
    axis.set_title("sunny scene lit by")
    cornell = result["cornell"]
    axis = chart.add_subplot(1, 3, 3)
    for clock, colour in (("wall", "tab:blue"), ("process_cpu", "tab:red")):
        ratios = cornell[f"round_ratios_{clock}"]
        median = cornell[f"ratio_{clock}"]
        axis.plot(range(1, len(ratios) + 1), ratios, "o-", color=colour, label=f"{clock}, median {median:.3f}")
        axis.axhline(median, color=colour, linestyle="--")
    axis.axhspan(2 - CORNELL_TARGET, CORNELL_TARGET, color="grey", alpha=0.2, label="within 3%")
    axis.set_xlabel("round")
    axis.set_ylabel(f"time, current / {cornell['baseline_revision']}")
    axis.set_title(f"Cornell box {result['cornell_size']}^2")
    axis.legend(fontsize=7)
    save_figure(chart, path, result, f"environment lighting, sunny scene {result['width']}^2, {result['spp']} spp")


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, spp=16, repeats=7)
    parser.add_argument("--size", type=int, default=128, help="sunny scene's width and height (default 128)")
    parser.add_argument("--reference-spp", type=int, default=4096, help="samples per pixel of the reference")
    parser.add_argument("--reference-batches", type=int, default=16, help="its batches, for its variance")
    parser.add_argument("--validation-spp", type=int, default=64, help="samples per pixel of each validation")
    parser.add_argument("--cost-spp", type=int, default=32, help="samples per pixel of a render timed for its cost")
    parser.add_argument("--cost-rounds", type=int, default=7, help="rounds of the cost per sample")
    parser.add_argument("--cornell-size", type=int, default=256, help="Cornell box width and height")
    parser.add_argument("--cornell-spp", type=int, default=16, help="samples per pixel of a timed Cornell box render")
    parser.add_argument("--cornell-rounds", type=int, default=15, help="rounds of the Cornell box A/B")
    parser.add_argument("--baseline", default=BASELINE_REVISION, help="revision the Cornell box is timed against")
    args = parse(
        parser,
        argv,
        "size",
        "reference_spp",
        "validation_spp",
        "cost_spp",
        "cost_rounds",
        "cornell_size",
        "cornell_spp",
        "cornell_rounds",
    )
    if not 2 <= args.reference_batches <= args.reference_spp:
        parser.error(f"--reference-batches must be from 2 to --reference-spp, got {args.reference_batches}")
    run = Run()
    texels = sunny_map()
    log(f"reference: {args.reference_spp} spp at {args.size}x{args.size}")
    reference_mean, reference_variance = reference(texels, args.size, args.reference_spp, args.reference_batches)
    renderers = method_renderers(texels, args.size)
    validation = validate_methods(renderers, reference_mean, args.validation_spp)
    methods = efficiency(renderers, reference_mean, reference_variance, args.spp, args.repeats)
    ratio = methods["importance sampled"]["efficiency"] / methods["uniform sphere"]["efficiency"]
    log(f"efficiency, importance sampled / uniform sphere: x{ratio:.1f}")
    costs = cost_per_sample(texels, args.size, args.cost_spp, args.cost_rounds)
    for lighting, entry in costs.items():
        log(
            f"{lighting:8s} environment: {entry['median_ns_per_path']:.0f} ns per path, x{entry['over_none']:.3f} none's"
        )
    cornell = cornell_against_baseline(args.baseline, args.cornell_size, args.cornell_spp, args.cornell_rounds)
    log(
        f"Cornell box, current / {args.baseline}: x{cornell['ratio_process_cpu']:.3f} CPU, x{cornell['ratio_wall']:.3f} wall"
    )
    result = {
        "scene": "sunny: a diffuse sphere on a plane under a generated sky with a small bright sun; the Cornell box",
        "width": args.size,
        "height": args.size,
        "spp": args.spp,
        "max_depth": MAX_DEPTH,
        "map": {
            "size": MAP_SIZE,
            "sun_direction": SUN_DIRECTION,
            "sun_diameter_degrees": SUN_DIAMETER_DEGREES,
            "sun_radiance": SUN_RADIANCE,
        },
        "repeats": args.repeats,
        "reference_spp": args.reference_spp,
        "reference_batches": args.reference_batches,
        "validation": validation,
        "efficiency": methods,
        "efficiency_ratio": ratio,
        "efficiency_target": EFFICIENCY_TARGET,
        "cost_spp": args.cost_spp,
        "cost_rounds": args.cost_rounds,
        "cost_per_sample": costs,
        "cornell_size": args.cornell_size,
        "cornell_spp": args.cornell_spp,
        "cornell_rounds": args.cornell_rounds,
        "cornell": cornell,
    }
    write_result("environment", result, out=args.out, plot=plot, run=run)
    print(
        f"importance sampling x{ratio:.1f} as efficient as uniform (target >= {EFFICIENCY_TARGET:g}); "
        f"map / none x{costs['map']['over_none']:.3f}, constant / none x{costs['constant']['over_none']:.3f} per sample; "
        f"Cornell box current / {args.baseline} x{cornell['ratio_process_cpu']:.3f} by CPU time (target <= {CORNELL_TARGET})"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
