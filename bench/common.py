"""What every benchmark shares: its arguments, the checks before timing, the timed render, error
measures against a reference, the scenes several of them use, Mitsuba on the other side, the result
file and its chart.

A benchmark is a module run as `python -m bench.<name>` from the checkout's root, with a
`main(argv)` that builds its parser with `argument_parser`, validates before it times, and writes
through `write_result`: the one way a result is written, with the metadata every result carries
(git revision, adapter and driver, CPU, versions, machine load).
"""

from __future__ import annotations

import argparse
import importlib.util
import itertools
import json
import math
import os
import platform
import re
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from types import ModuleType

import numpy as np

from wgputrace import Camera, Diffuse, Emitter, Renderer, Scene, Shape, make_plane
from wgputrace.bvh import BVH
from wgputrace.cli_arguments import parse_size
from wgputrace.render.ray_count import RayCounts, count_rays
from wgputrace.testing.stats import sidak, z_limit

REPO_ROOT = Path(__file__).resolve().parent.parent
RESULTS_DIR = REPO_ROOT / "bench" / "results"


# -- arguments ------------------------------------------------------------------------------------


def argument_parser(
    doc: str,
    *,
    size: tuple[int, int] | None = None,
    spp: int | None = None,
    repeats: int | None = None,
    seed: int | None = None,
) -> argparse.ArgumentParser:
    """A parser described by the first paragraph of `doc`, with --out and, for each default given,
    the option every benchmark spells the same way; `parse` checks the counts."""
    parser = argparse.ArgumentParser(description=" ".join(doc.split("\n\n")[0].split()))
    if size is not None:
        parser.add_argument("--size", type=parse_size, default=size, help=f"WIDTHxHEIGHT (default {size[0]}x{size[1]})")
    if spp is not None:
        parser.add_argument("--spp", type=int, default=spp, help=f"samples per pixel of a timed render (default {spp})")
    if repeats is not None:
        parser.add_argument("--repeats", type=int, default=repeats, help=f"timed runs; medians (default {repeats})")
    if seed is not None:
        parser.add_argument("--seed", type=int, default=seed, help=f"random seed (default {seed})")
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    return parser


def parse(parser: argparse.ArgumentParser, argv: list[str] | None, *counts: str) -> argparse.Namespace:
    """Parse `argv`; every option named in `counts` (and --spp, --repeats where present) must be at least 1."""
    args = parser.parse_args(argv)
    names = dict.fromkeys([*(name for name in ("spp", "repeats") if hasattr(args, name)), *counts])
    low = [f"--{name.replace('_', '-')} {getattr(args, name)}" for name in names if np.min(getattr(args, name)) < 1]
    if low:
        parser.error(f"must be at least 1: {', '.join(low)}")
    return args


def log(message: str) -> None:
    """Progress, on stderr: stdout holds the summary."""
    print(message, file=sys.stderr, flush=True)


# -- validation before timing ---------------------------------------------------------------------

CHANNELS = ("red", "green", "blue")


def sidak_critical_z(family_significance: float, tests: int) -> float:
    """Two-sided standard-normal bound so that `tests` tests together err with that probability.

    Sidak's bound holds for two-sided z-tests on jointly normal statistics whatever their
    correlation, and the channels of one image are strongly correlated."""
    return z_limit(sidak(family_significance, tests))


def agreement(image: np.ndarray, baseline: np.ndarray, z_critical: float) -> dict:
    """Paired z-test per channel that two images have the same expected mean radiance.

    D_p = image_p - baseline_p per pixel p (P pixels). Every pixel has its own random stream, so the
    D_p are independent of each other, and if both images estimate the same picture, E[D_p] = 0.
    The image mean of D then has variance Var(D)/P, estimated by the sample variance of the D_p:
    the standard error comes from the per-pixel spread of the differences, which holds only noise,
    not the picture (the picture cancels in D). With P in the thousands, mean(D)/SE is standard
    normal. This holds whatever the correlation between the two images, so the same test serves
    images from the same random numbers (the spread is then small and the test sharp; identical
    images give D = 0 and pass) and from independent ones.
    """
    differences = (image.astype(np.float64) - baseline.astype(np.float64)).reshape(-1, 3)
    mean = differences.mean(axis=0)
    standard_error = differences.std(axis=0, ddof=1) / math.sqrt(len(differences))
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


def image_failures(image: np.ndarray, dropped: int, band: tuple[float, float] | None = None) -> list[str]:
    """What is wrong with one image on its own: non-finite values, samples the shader dropped, and
    (where `band` is given) a mean radiance outside it, a coarse gate against missing lights or
    exploding path weights, not an accuracy test."""
    failures = []
    finite = np.isfinite(image)
    if not finite.all():
        failures.append(f"{np.count_nonzero(~finite)} image values are NaN or infinite")
    if dropped:
        failures.append(f"the shader dropped {dropped} samples (non-finite or cut short)")
    if band is not None and finite.all():
        mean = float(np.mean(image, dtype=np.float64))
        if not band[0] <= mean <= band[1]:
            failures.append(f"mean radiance {mean:.4g} is outside the sane band [{band[0]}, {band[1]}]")
    return failures


def bvh_failures(bvh: BVH, vertices: np.ndarray) -> list[str]:
    """What makes a tree over `vertices` ((N, 3, 3) corners) invalid: its triangle order not a
    permutation, a triangle in no leaf or in two, a root box other than the mesh's bounds."""
    failures = []
    count = len(vertices)
    if not np.array_equal(np.sort(bvh.triangle_order), np.arange(count)):
        failures.append("triangle_order is not a permutation of the triangles")
    leaves = bvh.triangle_count > 0
    first, size = bvh.left_or_first[leaves].astype(np.int64), bvh.triangle_count[leaves].astype(np.int64)
    # every slot of every leaf's range [first, first + size), as one flat array
    slots = np.repeat(first - (np.cumsum(size) - size), size) + np.arange(size.sum())
    covered = np.bincount(slots, minlength=count)
    if not np.all(covered == 1):
        failures.append(f"{np.count_nonzero(covered != 1)} triangle slots are not in exactly one leaf")
    corners = vertices.reshape(-1, 3)
    if not (
        np.array_equal(bvh.bounds_min[0], corners.min(axis=0))
        and np.array_equal(bvh.bounds_max[0], corners.max(axis=0))
    ):
        failures.append(f"root box {bvh.bounds_min[0]} .. {bvh.bounds_max[0]} is not the mesh's bounds")
    return failures


# -- timed renders --------------------------------------------------------------------------------


def fresh_image(renderer: Renderer, spp: int, *, from_seed: bool = False) -> tuple[np.ndarray, int, float, float]:
    """Forget earlier samples, render `spp`: (image, dropped samples, wall seconds, process CPU seconds).

    The random sequences continue (new, independent samples), or with `from_seed` start again at
    the seed (the same samples as every other render from the seed). Only the render is timed: the
    clear of the accumulation buffer is waited for before the clock starts, and the read-back of
    the image happens after it stops. Process CPU time includes llvmpipe's worker threads and
    hardly changes with other load on a CPU adapter's cores, which wall time does.
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


@dataclass
class Timed:
    """One measured kind of work: `units` (paths or rays) per run, wall and process CPU seconds per run."""

    units: int
    wall: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)

    def add(self, wall: float, cpu: float) -> None:
        self.wall.append(wall)
        self.cpu.append(cpu)

    def entry(self, unit: str = "paths") -> dict:
        """Runs, medians and the rate of the median run, for the result file."""
        median = statistics.median(self.wall)
        return {
            f"{unit}_per_run": self.units,
            "run_seconds": self.wall,
            "run_process_cpu_seconds": self.cpu,
            "median_seconds": median,
            "median_process_cpu_seconds": statistics.median(self.cpu),
            f"{unit}_per_second": self.units / median,
        }


def counted_rays(renderer: Renderer, spp: int, timed_image: np.ndarray) -> RayCounts:
    """Count the rays of a timed render of `spp` from the seed: the same samples again through the
    path tracer with ray counters compiled in, whose image must equal `timed_image` bit for bit
    (the proof that the counts belong to the timed paths)."""
    renderer.restart()
    counts = count_rays(renderer, spp)
    if not np.array_equal(renderer.image(), timed_image):
        raise SystemExit("the counted render's image differs from the timed one's")
    return counts


def ray_rates(counts: RayCounts, seconds: float) -> dict:
    """Camera rays and all rays (camera, extension, shadow) per second of a render that took `seconds`."""
    return {
        "camera_rays_per_second": counts.camera / seconds,
        "rays_per_second": counts.total / seconds,
        "rays_per_path": counts.total / counts.camera,
        "rays": {"camera": counts.camera, "extension": counts.extension, "shadow": counts.shadow, "all": counts.total},
    }


# -- error against a reference --------------------------------------------------------------------

# relative MSE = mean((ours - reference)^2 / (reference^2 + this)): dark pixels do not dominate
RELATIVE_MSE_EPSILON = 1e-2
# Power laws are fitted from this many samples per pixel on: the first few checkpoints are
# dominated by the odd first sample and by what a single image happens to hit.
FIT_MIN_SPP = 4


def errors(image: np.ndarray, reference_mean: np.ndarray, reference_variance: np.ndarray) -> dict:
    """Our MSE and relative MSE with the reference's own variance taken out, and the raw MSE.

    Ours and the reference are independent, so E[(ours - reference)^2] = our MSE + the reference's
    variance: subtracted, what remains is our error alone."""
    squared = (image.astype(np.float64) - reference_mean) ** 2
    mse = float(np.mean(squared - reference_variance))
    relative = float(np.mean((squared - reference_variance) / (reference_mean**2 + RELATIVE_MSE_EPSILON)))
    return {"rmse": float(np.sqrt(max(mse, 0.0))), "relative_mse": relative, "raw_mse": float(np.mean(squared))}


def checkpoints(max_spp: int) -> list[int]:
    """1, 2, 4, ... max_spp: where a progressive render is read back."""
    return [1 << k for k in range(max_spp.bit_length()) if 1 << k <= max_spp]


def fit_slope(x: Sequence[float], y: Sequence[float]) -> float:
    """Least-squares slope of log y against log x (positive values only)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    keep = (x > 0) & (y > 0)
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def curves(rows: list[dict]) -> dict:
    """Per scene and integrator ("scene/integrator"): per checkpoint the MSEs averaged over runs,
    the median time, and the slopes of the log-log curves from FIT_MIN_SPP on."""
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


def add_max_spp(parser: argparse.ArgumentParser, default: int) -> None:
    """--max-spp, the last checkpoint of a convergence curve: a power of two leaving a few to fit."""

    def power_of_two(text: str) -> int:
        value = int(text)
        if value < FIT_MIN_SPP * 4 or value & (value - 1):
            raise argparse.ArgumentTypeError(f"must be a power of two >= {FIT_MIN_SPP * 4}, got {value}")
        return value

    parser.add_argument("--max-spp", type=power_of_two, default=default, help=f"last checkpoint (default {default})")


# -- scenes and rays ------------------------------------------------------------------------------

# The sheet spans [-1, 1]^2 with heights within +-0.1; from this height a 50-degree view sees a
# square of half-width 0.75 at most: the sheet fills the image at every triangle count.
SHEET_CAMERA_HEIGHT = 1.5
SHEET_VFOV_DEGREES = 50.0
SHEET_LAMP = {"height": 3.0, "size": 1.0, "emittance": 20.0}
# The height field of bench.big_mesh and bench.bvh_build_baseline: 2 x 708^2 = 1,002,528 triangles.
BIG_MESH_CELLS = 708
# The counts the sheet is rendered (bench.scaling) and built (bench.bvh_build) at.
TRIANGLE_COUNTS = (10, 100, 1_000, 10_000, 100_000, 1_000_000)


def height_field(cells: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertices ((cells + 1)^2, 3) and faces (2 cells^2, 3) of a wavy sheet over [-1, 1]^2, facing +y."""
    x, z = np.meshgrid(np.linspace(-1, 1, cells + 1), np.linspace(-1, 1, cells + 1), indexing="ij")
    y = 0.1 * np.sin(9 * x) * np.cos(7 * z)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    a = (i * (cells + 1) + j).ravel()
    b, c, d = a + 1, a + cells + 1, a + cells + 2
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    return vertices, faces


def sheet_scene(triangles: int) -> Scene:
    """The height field with about `triangles` triangles (2 cells^2) seen from straight above, lit
    by a square lamp above the camera and out of view: it fills the image at every count."""
    cells = max(1, round(math.sqrt(triangles / 2)))
    vertices, faces = height_field(cells)
    sheet = Shape("sheet", vertices[faces], Diffuse("sheet", color=(0.7, 0.7, 0.7)))
    lamp = make_plane(
        (0, SHEET_LAMP["height"], 0),
        (np.pi, 0, 0),
        (SHEET_LAMP["size"], SHEET_LAMP["size"]),
        Emitter("lamp", emittance=SHEET_LAMP["emittance"]),
        "lamp",
    )
    # looking straight down, with +z as the picture's up (an exactly vertical up vector would be degenerate)
    camera = Camera.looking_at((0, SHEET_CAMERA_HEIGHT, -1e-3), (0, 0, 0), vfov_degrees=SHEET_VFOV_DEGREES)
    return Scene([sheet, lamp], camera)


def pixel_centre_rays(camera: Camera, width: int, height: int, dtype=np.float32) -> tuple[np.ndarray, np.ndarray]:
    """(origins, unit directions), (width * height, 3), row 0 at the top: camera/camera_ray.wgsl's
    camera_ray with the jitter at the pixel centre."""
    right, up, forward = camera.image_plane(width, height)
    x = (np.arange(width) + 0.5) / width * 2.0 - 1.0
    y = (np.arange(height) + 0.5) / height * 2.0 - 1.0
    directions = forward + x[None, :, None] * right - y[:, None, None] * up
    directions = (directions / np.linalg.norm(directions, axis=-1, keepdims=True)).reshape(-1, 3)
    origins = np.broadcast_to(np.asarray(camera.position, np.float64), directions.shape)
    return origins.astype(dtype), directions.astype(dtype)


# -- Mitsuba 3 on the other side ------------------------------------------------------------------


def mitsuba_missing() -> str | None:
    """Why Mitsuba's `llvm_ad_rgb` cannot run here, or None."""
    from wgputrace.reference.mitsuba_scene import libllvm_path

    # found, not imported: importing starts drjit, which then no longer reads DRJIT_CACHE_DIR
    if importlib.util.find_spec("mitsuba") is None:
        return "mitsuba is not installed: pip install -e '.[reference]'"
    if libllvm_path() is None:
        return "Mitsuba's llvm_ad_rgb needs LLVM >= 16: install Debian's libllvm19 or set DRJIT_LIBLLVM_PATH"
    return None


def record_skip(name: str, settings: dict, reason: str, out: Path) -> int:
    """File why `name` did not run as <name>_skipped_<adapter>.json; the suite reports it as skipped."""
    write_result(f"{name}_skipped", {**settings, "skipped": reason}, out=out)
    print(f"{name} skipped: {reason} (recorded in {result_stem(f'{name}_skipped', out)}.json)")
    return 0


def threads(drjit: ModuleType) -> dict:
    """The threads both renderers run on the shared cores: llvmpipe's (one per core unless
    LP_NUM_THREADS says otherwise) and drjit's pool."""
    return {
        "llvmpipe": int(os.environ.get("LP_NUM_THREADS") or os.cpu_count()),
        "drjit": drjit.thread_count(),
        "cpu_count": os.cpu_count(),
    }


# Far above any reference seed (0 .. passes - 1): reusing one would correlate a comparison's error
# with the reference's.
MITSUBA_SEED_START = 1_000_000


@dataclass
class MitsubaSide:
    """Mitsuba, its scenes by image size, and a seed that changes with every render."""

    mi: ModuleType
    dr: ModuleType
    scene_name: str
    seed_start: int = MITSUBA_SEED_START
    scenes: dict[int, object] = field(default_factory=dict)
    kernels: list[dict] = field(default_factory=list)  # drjit's history since the last kernel_report()

    def __post_init__(self) -> None:
        self.seeds = itertools.count(self.seed_start)

    def scene(self, size: int, max_depth: int):
        from wgputrace import load_scene
        from wgputrace.reference.mitsuba_scene import mitsuba_scene

        if size not in self.scenes:
            self.scenes[size] = mitsuba_scene(self.mi, load_scene(self.scene_name), size, size, max_depth)
        return self.scenes[size]

    def render(self, size: int, max_depth: int, spp: int) -> tuple[np.ndarray, float, float]:
        """A fresh image with a new seed: (image, wall seconds, process CPU seconds), evaluation included."""
        scene = self.scene(size, max_depth)
        image, wall, cpu = self.timed(lambda: self.mi.render(scene, spp=spp, seed=next(self.seeds)))
        return np.asarray(image, dtype=np.float32), wall, cpu

    def timed(self, launch: Callable[[], object]):
        """(result of `launch`, wall seconds, process CPU seconds), every output evaluated and waited for."""
        self.dr.sync_thread()
        wall, cpu = time.perf_counter(), time.process_time()
        result = launch()
        self.dr.eval(result)  # drjit is lazy: the kernel runs here
        self.dr.sync_thread()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        self.kernels += [entry for entry in self.dr.kernel_history() if entry["type"] == self.dr.KernelType.JIT]
        return result, wall, cpu

    def kernel_report(self) -> dict:
        """The JIT kernels launched since the last report: compiled, loaded from disk, or reused from memory."""
        kernels, self.kernels = self.kernels, []
        compiled = [k for k in kernels if not k["cache_hit"]]
        return {
            "launches": len(kernels),
            "compiled": len(compiled),
            "loaded_from_disk_cache": sum(1 for k in kernels if k["cache_hit"] and k["cache_disk"]),
            "reused_from_memory": sum(1 for k in kernels if k["cache_hit"] and not k["cache_disk"]),
            "codegen_ms": sum(k["codegen_time"] for k in kernels),
            "llvm_backend_ms": sum(k["backend_time"] for k in kernels),
        }

    def compiled_nothing(self, what: str) -> dict:
        """The kernel report of timed work, which must not have compiled: the warm-up compiles."""
        report = self.kernel_report()
        if report["compiled"]:
            raise SystemExit(f"Mitsuba compiled {report['compiled']} kernels during {what}: the warm-up missed them")
        return report


# -- result files ---------------------------------------------------------------------------------


def git(*arguments: str, repo: Path = REPO_ROOT) -> str:
    """The output of `git ARGUMENTS` in the checkout; CalledProcessError (with git's stderr) if it fails."""
    return subprocess.run(["git", *arguments], cwd=repo, capture_output=True, text=True, check=True).stdout.strip()


def git_revision(repo: Path = REPO_ROOT) -> str:
    """`git rev-parse --short HEAD`, plus "-dirty" when anything outside bench/results differs from HEAD.

    Untracked files count: a module not yet committed is still code that ran. Result files do not,
    so a previous run's output cannot mark the next run dirty.
    """
    try:
        head = git("rev-parse", "--short", "HEAD", repo=repo)
        changes = git("status", "--porcelain", "--", ".", ":(exclude)bench/results", repo=repo)
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return f"{head}-dirty" if changes else head


def slug(*parts: str) -> str:
    """File-name-safe lower-case words joined by '-': ("llvmpipe (LLVM 15.0.6)", "Vulkan") -> llvmpipe-llvm-15-0-6-vulkan."""
    return "-".join(word for part in parts for word in re.findall(r"[a-z0-9]+", part.lower()))


def cpu_model() -> str:
    """The processor's name, which a CPU adapter's speed depends on as much as on its core count."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def environment() -> dict:
    """Versions and machine facts that change benchmark numbers."""
    import wgpu
    import wgpu.backends.wgpu_native as wgpu_native

    import wgputrace
    from wgputrace.gpu.device import describe

    return {
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "wgpu": wgpu.__version__,
        "wgpu_native": wgpu_native.__version__,
        "wgputrace": wgputrace.__version__,
        # the driver and its version, e.g. "Mesa 22.3.6 (LLVM 15.0.6)": lavapipe's speed changes with Mesa's
        "driver": describe()["description"],
        "platform": platform.platform(),
        "cpu": cpu_model(),
        "cpu_count": os.cpu_count(),
        # llvmpipe runs one thread per core unless told otherwise.
        "LP_NUM_THREADS": os.environ.get("LP_NUM_THREADS"),
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
    }


def load_average() -> list[float] | None:
    """1/5/15-minute load: other processes on a CPU adapter's cores slow it down."""
    try:
        return [round(value, 2) for value in os.getloadavg()]
    except OSError:
        return None


@dataclass
class Run:
    """A benchmark's start and the machine's load then; `write_result` records both ends."""

    started: float = field(default_factory=time.perf_counter)
    load_before: list[float] | None = field(default_factory=load_average)

    def record(self) -> dict:
        return {
            "load_average_before_after": [self.load_before, load_average()],
            "wall_seconds": time.perf_counter() - self.started,
        }


def write_json(path: Path, data: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2) + "\n")


# What a result file must say about the picture it measured; None where one does not apply (a BVH
# build renders nothing), so a missing key is always an oversight.
SETTINGS_KEYS = ("scene", "width", "height", "spp", "max_depth")


def result_stem(name: str, out: Path = RESULTS_DIR) -> Path:
    """out/<name>_<adapter slug>: results from different adapters sit side by side."""
    from wgputrace.gpu.device import describe

    adapter = describe()
    return out / f"{name}_{slug(adapter['adapter'], adapter['backend'])}"


def write_result(
    name: str,
    data: dict,
    *,
    out: Path = RESULTS_DIR,
    plot: Callable[[Path, dict], None] | None = None,
    run: Run | None = None,
) -> dict[str, Path]:
    """Write `data` with the metadata every result carries as <stem>.json (stem: `result_stem`), and
    `plot(png_path, result)` as <stem>.png where given; says where on stderr and returns the paths
    by kind ("json", "png").

    The metadata (benchmark name, git revision, adapter, versions, load average now; with `run`,
    the load when it started and its wall time) comes first in the file and is what `plot` sees
    too, so a chart can name adapter and revision. `data` must hold SETTINGS_KEYS.
    """
    from wgputrace.gpu.device import describe

    missing = [key for key in SETTINGS_KEYS if key not in data]
    if missing:
        raise ValueError(f"the {name} result lacks {', '.join(missing)}: record each, None where it does not apply")
    result = {
        "benchmark": name,
        "git_revision": git_revision(),
        "adapter": describe(),
        "environment": environment(),
        "load_average_at_write": load_average(),
        **(run.record() if run else {}),
        **data,
    }
    stem = result_stem(name, out)
    paths = {"json": stem.with_suffix(".json")}
    write_json(paths["json"], result)
    if plot is not None:
        paths["png"] = stem.with_suffix(".png")
        plot(paths["png"], result)
    log(f"wrote {' and '.join(str(path) for path in paths.values())}")
    return paths


def write_csv(name: str, rows: list[dict], columns: Sequence[str], out: Path) -> Path:
    """Rows (dicts with `columns`) as <stem>.csv beside the JSON."""
    path = result_stem(name, out).with_suffix(".csv")
    lines = [",".join(columns)] + [",".join(str(row[column]) for column in columns) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    log(f"wrote {path}")
    return path


# -- charts ---------------------------------------------------------------------------------------


def figure(width: float, height: float):
    """A matplotlib Figure drawn off screen (no pyplot state, no display needed)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    chart = Figure(figsize=(width, height))
    FigureCanvasAgg(chart)
    return chart


def save_figure(chart, path: Path, result: dict, title: str, *, fontsize: float = 9, dpi: int = 110) -> None:
    """Title the chart with `title` and the adapter and revision that made `result`, and save it."""
    adapter = result["adapter"]
    chart.suptitle(
        f"{title}\n{adapter['adapter']} ({adapter['backend']}), rev {result['git_revision']}, "
        f"{result['environment']['cpu_count']} cores, load {result.get('load_average_before_after', ['-'])[0]}",
        fontsize=fontsize,
    )
    chart.tight_layout()
    chart.savefig(path, dpi=dpi)
