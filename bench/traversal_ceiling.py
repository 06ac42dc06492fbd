"""The ceiling on this adapter: our camera-ray traversal against Embree's (through Mitsuba 3's
`llvm_ad_rgb`), and the paths/s we could reach if every ray cost as little as a camera ray.

    python -m bench.traversal_ceiling
    python -m bench.traversal_ceiling --spp 2 --primary-spp 8 --repeats 3

Issue 8 asks for our paths/s on the Cornell box at 512x512 to equal Mitsuba's path tracer's; this
asks whether a path tracer on our traversal could reach it at all. In one process, on the same
scene (`mitsuba_scene` builds Mitsuba's from ours), `measure` times each kind of work in WHAT:
ours at full depth and at max depth 1 (each camera ray's closest hit and nothing else), Embree's
queries of one ray per pixel centre, and Mitsuba's path tracer at both depths, after validating
both traversals and both pictures. Without mitsuba or LLVM >= 16 this skips, recording why.
Writes bench/results/traversal_ceiling_<adapter>.json and .png.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.mitsuba import MitsubaSide, mitsuba_missing, threads
from bench.provenance import Run
from bench.result_files import record_skip, write_result
from bench.scenes import pixel_centre_rays
from bench.timing import Timed, counted_rays, fresh_image, ray_rates
from bench.validation import CHANNELS, agreement, sidak_critical_z
from wgputrace import Renderer, load_scene
from wgputrace.kernels.structs import NO_TRIANGLE
from wgputrace.reference.mitsuba_scene import (
    EMITTER_BACK_OFFSET_RELATIVE,
    LLVM_VARIANT,
    libllvm_path,
    load_mitsuba,
)
from wgputrace.render.lights import emitting_kinds
from wgputrace.render.ray_count import count_rays
from wgputrace.testing.oracles import record_corners
from wgputrace.testing.references import load_reference
from wgputrace.testing.traversal import closest_hit

NAME = "traversal_ceiling"
SCENE = "cornell"
SIZE = 512  # issue 8's paths/s target is at 512x512
PRIMARY_DEPTH = 1  # max depth 1: the camera ray's closest hit, the emission of a lamp seen there
# Family-wise false-alarm rate of the two radiance agreement tests (ours vs Mitsuba at full depth
# and at depth 1), Sidak-corrected over both and every channel.
AGREEMENT_SIGNIFICANCE = 1e-3
AGREEMENT_TESTS = 2 * len(CHANNELS)
# Hit distances of the same ray from our closest_hit and Embree: both intersect the same float32
# triangles, so they differ by float32 rounding (about 1e-7 relative) unless the engines pick
# different surfaces, which a ray through a shared edge or a corner may. A ray counts as agreeing
# within this relative difference (plus, on a lamp, the distance along the ray to Mitsuba's copy of
# it wound the other way, which `mitsuba_scene` moves EMITTER_BACK_OFFSET_RELATIVE behind it),
# and at most this fraction of rays may disagree.
DISTANCE_RTOL = 1e-4
MAX_DISAGREEING_FRACTION = 1e-3

# drjit compiles Mitsuba's path kernel again at its second render (the kernel history shows a new
# hash of the same size: a value the first render baked in, the seed by the look of it, becomes an
# input once it changes), so the warm-up renders twice.
MITSUBA_WARMUP_RENDERS = 2

OURS_FULL, OURS_PRIMARY = "ours_full", "ours_camera_rays"
EMBREE, EMBREE_PRELIMINARY = "embree_ray_intersect", "embree_ray_intersect_preliminary"
MITSUBA_FULL, MITSUBA_PRIMARY = "mitsuba_path", "mitsuba_path_depth_1"
FULL_PATHS = (OURS_FULL, MITSUBA_FULL)  # measured in paths of full depth; the others in camera rays
WHAT = {
    OURS_FULL: "ours: path tracer (MIS) at max depth {max_depth}",
    OURS_PRIMARY: "ours: max depth 1 (camera rays' closest hit only)",
    EMBREE: "Mitsuba ray_intersect (Embree + SurfaceInteraction) of pixel-centre rays",
    EMBREE_PRELIMINARY: "Mitsuba ray_intersect_preliminary (Embree: distance, primitive)",
    MITSUBA_FULL: "Mitsuba path integrator at max depth {max_depth}",
    MITSUBA_PRIMARY: "Mitsuba path integrator at max depth 1",
}


class Embree:
    """Mitsuba's scene intersection of fixed rays, evaluated in full and waited for."""

    def __init__(self, mitsuba: MitsubaSide, scene, origins: np.ndarray, directions: np.ndarray) -> None:
        mi, dr = mitsuba.mi, mitsuba.dr
        self.mitsuba, self.scene = mitsuba, scene
        columns = [[mi.Float(np.ascontiguousarray(array[:, k])) for k in range(3)] for array in (origins, directions)]
        self.ray = mi.Ray3f(mi.Point3f(*columns[0]), mi.Vector3f(*columns[1]))
        dr.eval(self.ray)  # the rays exist before any timing starts

    def intersect(self, preliminary: bool):
        """One launch over every ray, every field of the result evaluated: (result, wall seconds, process CPU seconds)."""
        if preliminary:  # coherent=True, as for camera rays
            return self.mitsuba.timed(lambda: self.scene.ray_intersect_preliminary(self.ray, True))
        return self.mitsuba.timed(lambda: self.scene.ray_intersect(self.ray, self.mitsuba.mi.RayFlags.All, True))


def hit_statistics(t: np.ndarray, hit: np.ndarray) -> dict:
    return {"hit_fraction": float(hit.mean()), "mean_distance": float(t[hit].mean(dtype=np.float64))}


def allowed_distance_difference(records, triangle: np.ndarray, t: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Per ray hitting our `triangle` at `t`: how far Embree's distance may lie from ours (see DISTANCE_RTOL)."""
    corners = record_corners(records.triangles).astype(np.float64)
    hit = triangle != NO_TRIANGLE
    mine = corners[np.where(hit, triangle, 0)]
    normals = np.cross(mine[:, 1] - mine[:, 0], mine[:, 2] - mine[:, 0])
    cos = np.abs(np.sum(normals * directions, axis=1)) / np.linalg.norm(normals, axis=1)
    kinds = records.materials["kind"][records.triangles["material"][np.where(hit, triangle, 0)]]
    # the magnitude `mitsuba_scene` scales the offset by: the largest corner coordinate
    offset = EMITTER_BACK_OFFSET_RELATIVE * float(np.max(np.abs(corners)))
    lamp = hit & np.isin(kinds, emitting_kinds())
    return DISTANCE_RTOL * t + np.where(lamp, offset / np.maximum(cos, np.finfo(np.float64).tiny), 0.0)


def validate_traversal(renderer: Renderer, embree: Embree, origins: np.ndarray, directions: np.ndarray) -> dict:
    """Our shipped closest_hit and both Embree queries on the same rays: same hits, same distances."""
    ours_t, triangle = closest_hit(renderer.context, renderer.records, origins, directions)
    ours_hit = triangle != NO_TRIANGLE
    allowed = allowed_distance_difference(renderer.records, triangle, ours_t, directions.astype(np.float64))
    engines = {"ours_closest_hit": (ours_t, ours_hit)}
    for name, preliminary in ((EMBREE, False), (EMBREE_PRELIMINARY, True)):
        hits = embree.intersect(preliminary)[0]
        t = np.asarray(hits.t, dtype=np.float64)
        engines[name] = (t, np.isfinite(t))
    failures = []
    comparisons = {}
    for name in (EMBREE, EMBREE_PRELIMINARY):
        t, hit = engines[name]
        both = hit & ours_hit
        agree = (hit == ours_hit) & (~both | (np.abs(t - ours_t) <= allowed))
        disagreeing = float(1.0 - agree.mean())
        comparisons[name] = {
            "disagreeing_fraction": disagreeing,
            "largest_relative_distance_difference_where_both_hit": float(
                np.max(np.abs(t[both] - ours_t[both]) / t[both])
            ),
        }
        if disagreeing > MAX_DISAGREEING_FRACTION:
            worst = int(np.argmax(~agree))
            failures.append(
                f"{name}: {disagreeing:.3g} of the rays disagree with ours (limit {MAX_DISAGREEING_FRACTION:g}); "
                f"first: ray {worst} ours t {ours_t[worst]:.6g} hit {ours_hit[worst]}, Embree t {t[worst]:.6g} "
                f"(allowed difference {allowed[worst]:.3g})"
            )
    if failures:
        raise SystemExit("traversal validation failed, nothing timed:\n  " + "\n  ".join(failures))
    summary = {name: hit_statistics(t, hit) for name, (t, hit) in engines.items()}
    log(f"validated traversal: {json.dumps(summary)}")
    return {
        "rays": "one through every pixel centre",
        "distance_rtol": DISTANCE_RTOL,
        "max_disagreeing_fraction": MAX_DISAGREEING_FRACTION,
        "engines": summary,
        "against_ours": comparisons,
    }


def validate_images(pairs: dict[str, tuple[np.ndarray, int, np.ndarray]]) -> dict:
    """Each (ours, ours' dropped samples, Mitsuba's) pair: finite, same expected mean radiance."""
    z_critical = sidak_critical_z(AGREEMENT_SIGNIFICANCE, AGREEMENT_TESTS)
    checks = {"significance_family_wise": AGREEMENT_SIGNIFICANCE, "z_critical": z_critical}
    failures = []
    for name, (ours, nonfinite, theirs) in pairs.items():
        check = agreement(ours, theirs, z_critical)
        check["ours_mean_radiance"] = float(ours.mean(dtype=np.float64))
        check["mitsuba_mean_radiance"] = float(theirs.mean(dtype=np.float64))
        if nonfinite or not np.isfinite(ours).all():
            check["failures"].append(
                f"ours: {nonfinite} samples dropped (non-finite or cut short) or non-finite pixels"
            )
        if not np.isfinite(theirs).all():
            check["failures"].append("Mitsuba: NaN or infinite pixels")
        failures += [f"{name}: {text}" for text in check["failures"]]
        checks[name] = check
    if failures:
        raise SystemExit("image validation failed, nothing timed:\n  " + "\n  ".join(failures))
    log(f"validated images: z within {z_critical:.2f}")
    return checks


def check_camera_rays_only(renderer: Renderer) -> dict:
    """Count one sample of the max-depth-1 kernel: one closest-hit ray per path and nothing more."""
    renderer.restart()
    rays = count_rays(renderer, 1)
    if rays.extension or rays.shadow:
        raise SystemExit(
            f"max depth {PRIMARY_DEPTH} traced {rays.extension} extension and {rays.shadow} shadow rays "
            f"besides its {rays.camera} camera rays: it is not camera rays only"
        )
    return {"camera": rays.camera, "extension": rays.extension, "shadow": rays.shadow}


def measure(args: argparse.Namespace, mitsuba: MitsubaSide, mitsuba_primary: MitsubaSide) -> dict:
    """Warm-ups (the first render of each kind compiles; their images are validated), validation of
    traversal and pictures, then `repeats` rounds of every kind of work in WHAT; medians, and the
    ratios three ways: of medians, median of per-round ratios, of process CPU time."""
    scene = load_scene(SCENE)
    depth = args.max_depth
    full = Renderer(scene, SIZE, SIZE, seed=args.seed, max_depth=depth)
    primary = Renderer(scene, SIZE, SIZE, seed=args.seed, max_depth=PRIMARY_DEPTH)
    origins, directions = pixel_centre_rays(scene.camera, SIZE, SIZE)
    embree = Embree(mitsuba, mitsuba.scene(SIZE, depth), origins, directions)

    # warm-ups (compiles), whose last images are also the validation images
    started = time.perf_counter()
    ours_full, ours_full_nonfinite = fresh_image(full, args.spp)[:2]
    ours_primary, ours_primary_nonfinite = fresh_image(primary, args.primary_spp)[:2]
    for _ in range(MITSUBA_WARMUP_RENDERS):
        theirs_full = mitsuba.render(SIZE, depth, args.spp)[0]
        theirs_primary = mitsuba_primary.render(SIZE, PRIMARY_DEPTH, args.primary_spp)[0]
    log(f"warm-ups: {time.perf_counter() - started:.1f} s")
    validation = {
        "traversal": validate_traversal(primary, embree, origins, directions),
        "images": validate_images(
            {
                f"max_depth_{depth}": (ours_full, ours_full_nonfinite, theirs_full),
                f"max_depth_{PRIMARY_DEPTH}": (ours_primary, ours_primary_nonfinite, theirs_primary),
            }
        ),
        "ours_max_depth_1_rays_per_sample": check_camera_rays_only(primary),
    }
    warmup_kernels = mitsuba.kernel_report() | {"depth_1": mitsuba_primary.kernel_report()}

    paths, rays = SIZE * SIZE * args.spp, SIZE * SIZE * args.primary_spp
    timed = {name: Timed(paths if name in FULL_PATHS else rays) for name in WHAT}
    timed_images: dict[str, np.ndarray] = {}

    def ours_full_run() -> tuple[float, float]:
        image, nonfinite, wall, cpu = fresh_image(full, args.spp, from_seed=True)
        if nonfinite or not np.array_equal(image, timed_images.setdefault(OURS_FULL, image)):
            raise SystemExit(f"{OURS_FULL}: dropped samples ({nonfinite}) or an image unlike the first run's")
        return wall, cpu

    def embree_run(preliminary: bool) -> Callable[[], tuple[float, float]]:
        def run() -> tuple[float, float]:
            seconds = [embree.intersect(preliminary)[1:] for _ in range(args.primary_spp)]
            return sum(s[0] for s in seconds), sum(s[1] for s in seconds)

        return run

    runs = {
        OURS_FULL: ours_full_run,
        OURS_PRIMARY: lambda: fresh_image(primary, args.primary_spp)[2:],
        EMBREE: embree_run(False),
        EMBREE_PRELIMINARY: embree_run(True),
        MITSUBA_FULL: lambda: mitsuba.render(SIZE, depth, args.spp)[1:],
        MITSUBA_PRIMARY: lambda: mitsuba_primary.render(SIZE, PRIMARY_DEPTH, args.primary_spp)[1:],
    }
    for repeat in range(args.repeats):
        for name, run in runs.items():
            timed[name].add(*run())
        log(f"round {repeat + 1}/{args.repeats}: " + ", ".join(f"{n} {t.wall[-1]:.2f} s" for n, t in timed.items()))
    timed_kernels = mitsuba.kernel_report() | {"depth_1": mitsuba_primary.kernel_report()}
    compiled = timed_kernels["compiled"] + timed_kernels["depth_1"]["compiled"]
    if compiled:
        raise SystemExit(f"Mitsuba compiled {compiled} kernels during timed runs: the warm-up missed them")

    full_rays = ray_rates(
        counted_rays(full, args.spp, timed_images[OURS_FULL]), statistics.median(timed[OURS_FULL].wall)
    )
    units = {name: "paths" if name in FULL_PATHS else "rays" for name in timed}
    entries = {
        name: {"what": WHAT[name].format(max_depth=depth), "unit": units[name], **timing.entry(units[name])}
        for name, timing in timed.items()
    }
    entries[OURS_FULL].update(full_rays)
    rays_per_path = full_rays["rays_per_path"]
    # Shadow rays stop at any hit and could in principle cost less than a camera ray; the bound with
    # them free counts closest-hit rays (camera and extension) alone.
    closest_hit_rays_per_path = (full_rays["rays"]["camera"] + full_rays["rays"]["extension"]) / paths

    def ratios(rate: Callable[[str], float]) -> dict:
        """The comparisons, from each measured kind's units of work per second. The ceiling is the
        paths/s of a path tracer whose every ray cost what our camera rays cost (the most coherent
        rays there are) and whose shading cost nothing."""
        ceiling = rate(OURS_PRIMARY) / rays_per_path
        free_shadow_rays = rate(OURS_PRIMARY) / closest_hit_rays_per_path
        return {
            "camera_rays_ours_over_embree_ray_intersect": rate(OURS_PRIMARY) / rate(EMBREE),
            "camera_rays_ours_over_embree_preliminary": rate(OURS_PRIMARY) / rate(EMBREE_PRELIMINARY),
            "camera_rays_ours_over_mitsuba_path_depth_1": rate(OURS_PRIMARY) / rate(MITSUBA_PRIMARY),
            "ceiling_paths_per_second": ceiling,
            "ceiling_over_mitsuba_path": ceiling / rate(MITSUBA_FULL),
            "ceiling_free_shadow_rays_paths_per_second": free_shadow_rays,
            "ceiling_free_shadow_rays_over_mitsuba_path": free_shadow_rays / rate(MITSUBA_FULL),
            "paths_ours_over_mitsuba_path": rate(OURS_FULL) / rate(MITSUBA_FULL),
            "ours_full_over_ceiling": rate(OURS_FULL) / ceiling,
        }

    # Background load drifts between rounds: the median of ratios taken within each round shows
    # whether it moved the ratio of medians; process CPU time hardly depends on it at all.
    rounds = [ratios(lambda name, k=k: timed[name].units / timed[name].wall[k]) for k in range(args.repeats)]
    return {
        "validation": validation,
        "warmup_kernels": warmup_kernels,
        "timed_kernels": timed_kernels,
        "measurements": entries,
        "rays_per_path": rays_per_path,
        "closest_hit_rays_per_path": closest_hit_rays_per_path,
        "ratios": ratios(lambda name: timed[name].units / statistics.median(timed[name].wall)),
        "ratios_median_of_rounds": {key: statistics.median(r[key] for r in rounds) for key in rounds[0]},
        "ratios_process_cpu": ratios(lambda name: timed[name].units / statistics.median(timed[name].cpu)),
    }


COLORS = {"ours": "#3b75af", "ceiling": "#9cc3e6", "mitsuba": "#c4452c"}
CAMERA_RAY_BARS = (
    (OURS_PRIMARY, "ours\nmax depth 1", "ours"),
    (MITSUBA_PRIMARY, "Mitsuba path\nmax depth 1", "mitsuba"),
    (EMBREE, "Embree\nray_intersect", "mitsuba"),
    (EMBREE_PRELIMINARY, "Embree\npreliminary", "mitsuba"),
)


def plot(path: Path, result: dict) -> None:
    """Camera rays/s (ours against Embree) and paths/s (ours, the ceiling, Mitsuba)."""
    chart = figure(13.0, 5.2)
    ray_axes, path_axes = chart.subplots(1, 2)
    measurements, ratios = result["measurements"], result["ratios"]
    rays = [measurements[name]["rays_per_second"] / 1e6 for name, _, _ in CAMERA_RAY_BARS]
    bars = ray_axes.bar(
        [label for _, label, _ in CAMERA_RAY_BARS], rays, color=[COLORS[kind] for *_, kind in CAMERA_RAY_BARS]
    )
    ray_axes.bar_label(bars, labels=[f"{value:.2f} M" for value in rays], padding=2)
    ray_axes.set_ylabel("million camera rays per second (median)")
    ray_axes.set_title(
        f"camera rays only, {result['primary_spp']} per pixel per run\nours / Embree = "
        f"{ratios['camera_rays_ours_over_embree_ray_intersect']:.3f} "
        f"(preliminary: {ratios['camera_rays_ours_over_embree_preliminary']:.3f})",
        fontsize=10,
    )
    full = measurements[OURS_FULL]
    paths = [
        full["paths_per_second"] / 1e6,
        ratios["ceiling_paths_per_second"] / 1e6,
        ratios["ceiling_free_shadow_rays_paths_per_second"] / 1e6,
        measurements[MITSUBA_FULL]["paths_per_second"] / 1e6,
    ]
    labels = [
        "ours",
        f"ceiling:\ncamera rays/s / {full['rays_per_path']:.2f}",
        f"ceiling, shadow\nrays free: / {result['closest_hit_rays_per_path']:.2f}",
        "Mitsuba path",
    ]
    colors = [COLORS["ours"], COLORS["ceiling"], COLORS["ceiling"], COLORS["mitsuba"]]
    bars = path_axes.bar(labels, paths, color=colors)
    path_axes.bar_label(bars, labels=[f"{value:.3f} M" for value in paths], padding=2)
    path_axes.set_ylabel("million paths per second (median)")
    path_axes.set_title(
        f"paths, max depth {result['max_depth']}, {result['spp']} spp per run: ours / Mitsuba = "
        f"{ratios['paths_ours_over_mitsuba_path']:.3f}\nceilings / Mitsuba = {ratios['ceiling_over_mitsuba_path']:.3f}, "
        f"{ratios['ceiling_free_shadow_rays_over_mitsuba_path']:.3f} (shadow rays free)",
        fontsize=10,
    )
    for axes, values in ((ray_axes, rays), (path_axes, paths)):
        axes.set_ylim(0, max(values) * 1.15)  # room for the labels above the bars
        axes.grid(axis="y", alpha=0.3)
        axes.set_axisbelow(True)
    title = (
        f"Ceiling against Mitsuba {result['mitsuba']} {result['variant']} (Embree), {result['scene']} "
        f"{result['width']}x{result['height']}; threads {', '.join(f'{k} {v}' for k, v in result['threads'].items())}"
    )
    save_figure(chart, path, result, title)


def summary(result: dict) -> str:
    lines = [f"traversal ceiling, {result['adapter']['adapter']}, rev {result['git_revision']}"]
    for name, entry in result["measurements"].items():
        unit = entry["unit"]
        lines.append(f"  {name:34s} {entry[f'{unit}_per_second'] / 1e6:9.4f} M {unit}/s  ({entry['what']})")
    lines.append("  ratios: of medians / median of rounds' / of process CPU")
    for name, value in result["ratios"].items():
        alternates = (result[key][name] for key in ("ratios_median_of_rounds", "ratios_process_cpu"))
        lines.append(f"  {name}: {value:.4g} / " + " / ".join(f"{other:.4g}" for other in alternates))
    lines.append(f"  load average before, after: {result['load_average_before_after']}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, spp=2, repeats=3, seed=1)
    parser.add_argument(
        "--primary-spp",
        type=int,
        default=8,
        help="camera rays per pixel of each timed camera-ray run (max depth 1, Embree launches; default 8)",
    )
    args = parse(parser, argv, "primary_spp")
    # the suite's max depth: the reference's, as `bench.versus_mitsuba`'s
    args.max_depth = load_reference(SCENE).metadata["max_depth"]
    settings = {"scene": SCENE, "width": SIZE, "height": SIZE, "spp": args.spp, "max_depth": args.max_depth}
    reason = mitsuba_missing()
    if reason:
        return record_skip(NAME, settings, reason, args.out)
    run = Run()
    import drjit

    mi = load_mitsuba(LLVM_VARIANT)
    drjit.set_flag(drjit.JitFlag.KernelHistory, True)
    # one side per max depth: MitsubaSide keeps one scene per image size
    measured = measure(args, MitsubaSide(mi, drjit, SCENE), MitsubaSide(mi, drjit, SCENE))
    result = {
        **settings,
        "primary_spp": args.primary_spp,
        "repeats": args.repeats,
        "seed": args.seed,
        "mitsuba": mi.__version__,
        "drjit": drjit.__version__,
        "variant": LLVM_VARIANT,
        "libllvm": libllvm_path(),
        "threads": threads(drjit),
        "timing": "wall clock per run; ours: Renderer.render after restart()/reset(), image read-back not timed; "
        "Embree: primary_spp launches of the pixel-centre rays, each evaluated in full and waited for; "
        "Mitsuba path: mi.render evaluated; rounds interleave every kind",
        **measured,
    }
    paths = write_result(NAME, result, out=args.out, plot=plot, run=run)
    print(summary(json.loads(paths["json"].read_text())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
