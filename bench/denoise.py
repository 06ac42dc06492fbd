"""Denoising against the Mitsuba 3 references: the raw mean, the viewer's a-trous filter, Intel Open
Image Denoise on the colour alone and OIDN guided by the renderer's albedo and normal, at 1, 4, 16
and 64 samples per pixel, on the test scenes with references; the time a raw render needs for the
picture guided OIDN makes from 4 spp; the denoiser's cost; and its bias on a converged picture.

    python -m bench.denoise
    python -m bench.denoise --scenes cornell glass_grazing --repeats 1 --bias-spp 256 --cap-spp 256

Per scene (`measure_scene`): renderers with guides on and off validated before anything is timed,
the guides' cost per sample (`guide_cost`), every method's PSNR and relative MSE at each --spp
level, the time to a usable picture (`usable_picture`) and the bias at --bias-spp (`bias`, the
issue's limit 1%); once, OIDN's seconds per megapixel at each quality (`denoiser_cost`). Without
pyoidn (the `denoise` extra) this skips, recording why. Writes bench/results/denoise_<adapter>.json
and .png.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.error_curves import checkpoints, errors
from bench.provenance import Run
from bench.result_files import record_skip, write_result
from bench.timing import fresh_image
from bench.validation import CHANNELS, agreement, image_failures, sidak_critical_z
from wgputrace import Renderer
from wgputrace.cli_arguments import parse_size
from wgputrace.denoise import INSTALL_HINT, QUALITIES, denoise, denoiser_available, denoiser_device
from wgputrace.scene import DegenerateTrianglesWarning
from wgputrace.scenes import DEFAULT_SCENE, scene_by_name
from wgputrace.testing.image_statistics import displayed_psnr
from wgputrace.testing.references import Reference, load_reference, reference_dir
from wgputrace.view import display as viewer_display
from wgputrace.view.banded import BandedRenderer

NAME = "denoise"
METHODS = ("raw", "atrous", "oidn_color", "oidn_guided")
LABELS = {
    "raw": "raw mean",
    "atrous": "viewer's a-trous filter",
    "oidn_color": "OIDN, colour only",
    "oidn_guided": "OIDN with albedo and normal",
}
# The quality `wgputrace render --denoise` and Renderer.image(denoised=True) use.
QUALITY = "high"
# The usable picture: what guided OIDN makes of this many samples per pixel.
USABLE_SPP = 4
# The issue's bias limit: a converged picture's 32x32-pixel block means may move by at most 1%.
BIAS_BLOCK = 32
BIAS_LIMIT = 0.01
VALIDATION_SPP = 16
VALIDATION_SIGNIFICANCE = 1e-3  # family-wise, over scenes x renderers x channels


def scenes_with_references() -> list[str]:
    """Every scene tests/references holds, the default scene first."""
    names = sorted(path.stem for path in reference_dir().glob("*.npz"))
    return sorted(names, key=lambda name: name != DEFAULT_SCENE)


# Measured by default: the scenes that had references when issue 16 asked for this benchmark (the
# README's table). Named, not globbed, so that a new reference changes neither the table's scenes
# nor the suite's run time; --scenes takes any scene with a reference.
SCENES = (DEFAULT_SCENE, "axis_boxes", "glass_grazing", "glossy_spheres", "slivers", "tiny_light")


def new_renderer(scene: str, reference: Reference, seed: int, guides: bool) -> Renderer:
    with warnings.catch_warnings():
        # the slivers scene drops its zero-area triangles on purpose (tests/scene checks the warning)
        warnings.simplefilter("ignore", DegenerateTrianglesWarning)
        return Renderer(
            scene_by_name(scene),
            reference.metadata["width"],
            reference.metadata["height"],
            seed=seed,
            max_depth=reference.metadata["max_depth"],
            guides=guides,
        )


def validation_failures(renderer: Renderer, reference: Reference, z_critical: float) -> list[str]:
    """The renderer's first image (it compiles the path tracer): finite, nothing dropped, mean
    radiance equal to the reference's; with guides, guides that denoise accepts."""
    renderer.render(VALIDATION_SPP)
    image = renderer.image()
    failures = image_failures(image, renderer.dropped_samples)
    failures += agreement(image, reference.estimate.mean.astype(np.float32), z_critical)["failures"]
    if renderer.guides_enabled and not failures:
        try:
            denoise(image, **renderer.guides(), quality=QUALITY)
        except ValueError as refused:
            failures.append(str(refused))
    renderer.reset()
    return failures


class AtrousFilter:
    """The viewer's pre-convergence filter on a Renderer's samples, headless, at the weight the viewer
    gives it at that many samples per pixel (as `bench.filter_psnr` measures it)."""

    def __init__(self, renderer: Renderer) -> None:
        self.banded = BandedRenderer(renderer)
        self.display = viewer_display.Display(self.banded)

    def __call__(self) -> np.ndarray:
        # The banded renderer counts the samples Renderer.render added (it keeps its count in the
        # renderer's stats). Filter them afresh rather than blend the mean with an older filtered image.
        self.display.camera_changed()
        self.display.render(viewer_display.ViewSettings(filter_enabled=True))
        return self.display.read_image()


class Pictures:
    """Every method's picture of a guides-on renderer's samples, and the denoiser's time per call."""

    def __init__(self, renderer: Renderer) -> None:
        self.renderer = renderer
        self.atrous = AtrousFilter(renderer)
        self.denoise_seconds: dict[str, list[float]] = {"oidn_color": [], "oidn_guided": []}

    def _denoised(self, method: str, image: np.ndarray, guides: dict[str, np.ndarray]) -> np.ndarray:
        start = time.perf_counter()
        denoised = denoise(image, **guides, quality=QUALITY)
        self.denoise_seconds[method].append(time.perf_counter() - start)
        if not np.all(np.isfinite(denoised)):
            raise SystemExit(f"{method}: OIDN returned non-finite pixels")
        return denoised

    def __call__(self) -> dict[str, np.ndarray]:
        image = self.renderer.image()
        return {
            "raw": image,
            "atrous": self.atrous(),
            "oidn_color": self._denoised("oidn_color", image, {}),
            "oidn_guided": self._denoised("oidn_guided", image, self.renderer.guides()),
        }


def guide_cost(with_guides: Renderer, without: Renderer, rounds: int, spp: int) -> dict:
    """Seconds per sample of fresh renders with guides and without, alternating ABBA so that load
    drifting over the run hits both alike; each image checked (finite, nothing dropped)."""
    seconds: dict[str, dict[str, list[float]]] = {"on": {"wall": [], "cpu": []}, "off": {"wall": [], "cpu": []}}
    for k in range(rounds):
        order = (("on", with_guides), ("off", without))
        for name, renderer in order if k % 2 == 0 else order[::-1]:
            image, dropped, wall, cpu = fresh_image(renderer, spp)
            failures = image_failures(image, dropped)
            if failures:
                raise SystemExit(f"guides {name}, round {k + 1}: {failures}")
            seconds[name]["wall"].append(wall / spp)
            seconds[name]["cpu"].append(cpu / spp)
    median = {name: {kind: statistics.median(runs) for kind, runs in entry.items()} for name, entry in seconds.items()}

    def median_ratio(kind: str) -> float:
        on, off = seconds["on"][kind], seconds["off"][kind]
        return statistics.median(a / b for a, b in zip(on, off, strict=True))

    return {
        "rounds": rounds,
        "spp_per_round": spp,
        "seconds_per_sample": seconds,
        "median_seconds_per_sample": median,
        "on_over_off": median_ratio("wall"),
        "on_over_off_cpu": median_ratio("cpu"),
        "on_over_off_of_medians": median["on"]["wall"] / median["off"]["wall"],
    }


def blocks(image: np.ndarray) -> np.ndarray:
    """(rows, BIAS_BLOCK, columns, BIAS_BLOCK, channels): the image cut into blocks."""
    height, width, channels = image.shape
    return image.astype(np.float64).reshape(height // BIAS_BLOCK, BIAS_BLOCK, width // BIAS_BLOCK, BIAS_BLOCK, channels)


def block_means(image: np.ndarray) -> np.ndarray:
    return blocks(image).mean(axis=(1, 3))


def block_noise(image: np.ndarray, reference: np.ndarray) -> float:
    """The largest relative standard error of a block mean of `image` (any channel): the spread of
    image - reference over the block's pixels, which is noise alone (each pixel has its own random
    stream), over sqrt(pixels), relative to the reference's block mean. Block differences of
    about this size are noise, not bias."""
    spread = blocks(image - reference).std(axis=(1, 3), ddof=1) / BIAS_BLOCK
    return float(np.max(spread / block_means(reference)))


def largest_block_shift(image: np.ndarray, baseline: np.ndarray) -> dict:
    """The largest relative difference of a 32x32 block mean (any channel) from the baseline's, and where."""
    relative = block_means(image) / block_means(baseline) - 1.0
    row, column, channel = np.unravel_index(int(np.argmax(np.abs(relative))), relative.shape)
    return {
        "largest": float(abs(relative[row, column, channel])),
        "signed": float(relative[row, column, channel]),
        "block_row": int(row),
        "block_column": int(column),
        "channel": CHANNELS[channel],
        "mean_abs": float(np.mean(np.abs(relative))),
    }


def bias(pictures: dict[str, np.ndarray], reference_mean: np.ndarray, spp: int) -> dict:
    """The denoised pictures' block means against the reference's and against the raw picture's."""
    result = {
        "spp": spp,
        "block": BIAS_BLOCK,
        "limit": BIAS_LIMIT,
        "raw_against_reference": largest_block_shift(pictures["raw"], reference_mean),
        "raw_largest_relative_standard_error": block_noise(pictures["raw"], reference_mean),
    }
    for method in ("oidn_color", "oidn_guided"):
        against_reference = largest_block_shift(pictures[method], reference_mean)
        shift = largest_block_shift(pictures[method], pictures["raw"])
        result[method] = {
            "against_reference": against_reference,
            "against_raw": shift,
            "holds_against_reference": against_reference["largest"] <= BIAS_LIMIT,
            "holds_against_raw": shift["largest"] <= BIAS_LIMIT,
        }
    return result


def spp_to_reach(target: float, spp: list[int], curve: list[float]) -> float | None:
    """The samples per pixel where the curve first reaches `target`, linear in log2(spp) between
    the checkpoints around it; None where it never does."""
    for k, value in enumerate(curve):
        if value >= target:
            if k == 0:
                return float(spp[0])
            low, high = math.log2(spp[k - 1]), math.log2(spp[k])
            return float(2.0 ** (low + (high - low) * (target - curve[k - 1]) / (value - curve[k - 1])))
    return None


def usable_picture(scene_result: dict, method: str) -> dict:
    """Seconds to `method`'s PSNR at USABLE_SPP: with it (render with guides where it takes them,
    plus the denoiser) and by the raw render alone."""
    target = scene_result["psnr"][method][str(USABLE_SPP)]["mean"]
    curve = scene_result["raw_curve"]
    cost = scene_result["guide_cost"]["median_seconds_per_sample"]
    render = cost["on" if method == "oidn_guided" else "off"]["wall"]
    denoised_seconds = USABLE_SPP * render + statistics.median(scene_result["denoise_seconds"][method])
    raw_spp = spp_to_reach(target, curve["spp"], curve["psnr"])
    raw_seconds = None if raw_spp is None else raw_spp * cost["off"]["wall"]
    return {
        "target_psnr_db": target,
        "denoised_seconds": denoised_seconds,
        "raw_spp_needed": raw_spp,
        "raw_seconds": raw_seconds,
        "raw_last_spp": curve["spp"][-1],
        "raw_last_seconds": curve["spp"][-1] * cost["off"]["wall"],
        "speedup": None if raw_seconds is None else raw_seconds / denoised_seconds,
    }


def summary(values: list[float]) -> dict:
    return {
        "mean": statistics.fmean(values),
        "stdev": statistics.stdev(values) if len(values) > 1 else 0.0,
        "runs": values,
    }


def measure_scene(scene: str, args: argparse.Namespace, z_critical: float) -> dict:
    """Both renderers validated, the guides' cost, then `repeats` progressive renders with guides on
    (new samples each): every method's PSNR on the displayed picture and relative MSE (`errors`) at
    each --spp level. The last repeat's raw picture is read at every power of two and goes on to
    --bias-spp, and on (at most to --cap-spp) until it reaches guided OIDN's PSNR at USABLE_SPP."""
    reference = load_reference(scene)
    mean, variance = reference.estimate.mean, reference.estimate.variance
    with_guides = new_renderer(scene, reference, args.seed, guides=True)
    without = new_renderer(scene, reference, args.seed, guides=False)
    for name, renderer in (("guides on", with_guides), ("guides off", without)):
        failures = validation_failures(renderer, reference, z_critical)
        if failures:
            raise SystemExit(f"{scene}, {name}: validation failed, nothing timed: {failures}")
    cost = guide_cost(with_guides, without, args.rounds, args.round_spp)
    pictures = Pictures(with_guides)
    levels = set(args.spp)
    psnr_runs = {method: {spp: [] for spp in args.spp} for method in METHODS}
    relative_runs = {method: {spp: [] for spp in args.spp} for method in METHODS}
    raw_curve = {"spp": [], "psnr": [], "relative_mse": []}

    def render_to(spp: int) -> None:
        with_guides.render(spp - with_guides.samples_per_pixel)
        if with_guides.dropped_samples:
            raise SystemExit(f"{scene}: {with_guides.dropped_samples} dropped samples")

    def add_raw_point(spp: int) -> None:
        image = with_guides.image()
        raw_curve["spp"].append(spp)
        raw_curve["psnr"].append(displayed_psnr(image, mean))
        raw_curve["relative_mse"].append(errors(image, mean, variance)["relative_mse"])

    for repeat in range(args.repeats):
        # the random streams go on: each repeat's samples are new ones
        with_guides.reset()
        last = repeat == args.repeats - 1
        for spp in checkpoints(args.spp[-1]):
            render_to(spp)
            if last:
                add_raw_point(spp)
            if spp in levels:
                for method, image in pictures().items():
                    psnr_runs[method][spp].append(displayed_psnr(image, mean))
                    relative_runs[method][spp].append(errors(image, mean, variance)["relative_mse"])
        log(
            f"{scene} repeat {repeat + 1}/{args.repeats}: "
            + ", ".join(
                f"{spp} spp " + "/".join(f"{psnr_runs[m][spp][-1]:.1f}" for m in METHODS) + " dB" for spp in args.spp
            )
        )
    # The last repeat goes on: to the bias measurement, and on until its raw picture reaches guided
    # OIDN's PSNR at USABLE_SPP (or the cap).
    target = statistics.fmean(psnr_runs["oidn_guided"][USABLE_SPP])
    spp = args.spp[-1]
    converged = bias(pictures(), mean, spp) if spp == args.bias_spp else None
    while spp < args.cap_spp and (spp < args.bias_spp or raw_curve["psnr"][-1] < target):
        spp *= 2
        render_to(spp)
        add_raw_point(spp)
        if spp == args.bias_spp:
            converged = bias(pictures(), mean, spp)
    log(f"{scene}: raw {raw_curve['psnr'][-1]:.1f} dB at {spp} spp against guided OIDN's {target:.1f} dB")
    result = {
        "reference": reference.metadata,
        "width": with_guides.width,
        "height": with_guides.height,
        "max_depth": with_guides.max_depth,
        "psnr": {m: {str(spp): summary(runs) for spp, runs in psnr_runs[m].items()} for m in METHODS},
        "relative_mse": {m: {str(spp): summary(runs) for spp, runs in relative_runs[m].items()} for m in METHODS},
        "raw_curve": raw_curve,
        "guide_cost": cost,
        "denoise_seconds": pictures.denoise_seconds,
        "bias": converged,
    }
    result["usable_picture"] = {method: usable_picture(result, method) for method in ("oidn_color", "oidn_guided")}
    return result


def denoiser_cost(size: tuple[int, int], repeats: int, seed: int) -> dict:
    """Seconds per megapixel of OIDN at each quality, colour only and guided, on a 4-spp Cornell box."""
    width, height = size
    renderer = Renderer(scene_by_name(DEFAULT_SCENE), width, height, seed=seed, guides=True)
    renderer.render(USABLE_SPP)
    image, guides = renderer.image(), renderer.guides()
    failures = image_failures(image, renderer.dropped_samples)
    if failures:
        raise SystemExit(f"denoiser cost image: {failures}")
    megapixels = width * height / 1e6
    costs = {}
    for quality in QUALITIES:
        for kind, given in (("color", {}), ("guided", guides)):
            denoise(image, **given, quality=quality)  # sets this configuration's filter up
            wall, cpu = [], []
            for _ in range(repeats):
                start_wall, start_cpu = time.perf_counter(), time.process_time()
                denoise(image, **given, quality=quality)
                wall.append(time.perf_counter() - start_wall)
                cpu.append(time.process_time() - start_cpu)
            costs[f"{quality}/{kind}"] = {
                "quality": quality,
                "guides": kind == "guided",
                "run_seconds": wall,
                "run_process_cpu_seconds": cpu,
                "seconds_per_megapixel": statistics.median(wall) / megapixels,
                "process_cpu_seconds_per_megapixel": statistics.median(cpu) / megapixels,
            }
            log(f"denoiser {quality}/{kind}: {costs[f'{quality}/{kind}']['seconds_per_megapixel']:.2f} s/MP")
    return {"scene": DEFAULT_SCENE, "width": width, "height": height, "spp": USABLE_SPP, "costs": costs}


def plot(path: Path, result: dict) -> None:
    scenes = result["scenes"]
    columns = min(3, len(scenes))
    rows = math.ceil(len(scenes) / columns)
    chart = figure(4.4 * columns, 3.6 * rows + 0.6)
    styles = {"raw": "o-", "atrous": "s-", "oidn_color": "^-", "oidn_guided": "D-"}
    for index, (scene, entry) in enumerate(scenes.items()):
        axes = chart.add_subplot(rows, columns, index + 1)
        levels = result["spp_levels"]
        for method in METHODS:
            means = [entry["psnr"][method][str(spp)]["mean"] for spp in levels]
            spread = [entry["psnr"][method][str(spp)]["stdev"] for spp in levels]
            axes.errorbar(levels, means, yerr=spread, fmt=styles[method], markersize=4, capsize=2, label=LABELS[method])
        curve = entry["raw_curve"]
        axes.plot(curve["spp"], curve["psnr"], ":", color="grey", label=f"raw, last repeat to {curve['spp'][-1]} spp")
        usable = entry["usable_picture"]["oidn_guided"]
        axes.axhline(usable["target_psnr_db"], color="grey", linewidth=0.6)
        reached = (
            f"raw reaches it at {usable['raw_spp_needed']:.0f} spp"
            if usable["raw_spp_needed"] is not None
            else f"raw short of it at {usable['raw_last_spp']} spp"
        )
        axes.set_title(
            f"{scene}: guided OIDN at {USABLE_SPP} spp {usable['target_psnr_db']:.1f} dB;\n{reached}", fontsize=8
        )
        axes.set_xscale("log", base=2)
        ticks = curve["spp"][:: max(1, len(curve["spp"]) // 6)]
        axes.set_xticks(ticks, [str(spp) for spp in ticks])
        axes.set_xlabel("samples per pixel", fontsize=8)
        axes.set_ylabel("PSNR (dB, displayed sRGB)", fontsize=8)
        axes.grid(alpha=0.3)
        if index == 0:
            axes.legend(fontsize=6, loc="lower right")
    title = (
        f"denoising against the Mitsuba references, {result['width']}x{result['height']}, "
        f"mean of {result['repeats']} repeats, OIDN on {result['denoiser_device']} (quality {QUALITY})"
    )
    save_figure(chart, path, result, title, fontsize=10)


def power_of_two(text: str) -> int:
    value = int(text)
    if value < 1 or value & (value - 1):
        raise argparse.ArgumentTypeError(f"must be a power of two, got {value}")
    return value


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, repeats=3, seed=1)
    parser.add_argument(
        "--scenes",
        nargs="+",
        choices=scenes_with_references(),
        default=list(SCENES),
        help=f"default: {' '.join(SCENES)}",
    )
    parser.add_argument("--spp", type=int, nargs="+", default=[1, 4, 16, 64], help="samples per pixel compared")
    parser.add_argument(
        "--bias-spp",
        type=power_of_two,
        default=1024,
        help="where the last repeat's denoised pictures are compared block by block (default 1024)",
    )
    parser.add_argument(
        "--cap-spp",
        type=power_of_two,
        default=4096,
        help="the most the last repeat renders for its raw picture to reach guided OIDN's (default 4096)",
    )
    parser.add_argument("--rounds", type=int, default=7, help="alternating renders, guides on and off (default 7)")
    parser.add_argument("--round-spp", type=int, default=16, help="samples per pixel of each (default 16)")
    parser.add_argument(
        "--denoise-size", type=parse_size, default=(512, 512), help="WIDTHxHEIGHT of the denoiser's cost"
    )
    parser.add_argument("--denoise-repeats", type=int, default=5, help="timed calls per configuration (default 5)")
    args = parse(parser, argv, "rounds", "round_spp", "denoise_repeats")
    if args.spp != sorted(set(args.spp)) or any(spp & (spp - 1) for spp in args.spp) or USABLE_SPP not in args.spp:
        parser.error(f"--spp must be ascending powers of two including {USABLE_SPP}, got {args.spp}")
    if not args.spp[-1] <= args.bias_spp <= args.cap_spp:
        parser.error(
            f"need the largest --spp <= --bias-spp <= --cap-spp, got {args.spp[-1]}, {args.bias_spp}, {args.cap_spp}"
        )
    settings = {"scene": args.scenes, "width": None, "height": None, "spp": args.spp, "max_depth": None}
    if not denoiser_available():
        return record_skip(NAME, settings, f"Intel Open Image Denoise is missing: {INSTALL_HINT}", args.out)
    run = Run()
    z_critical = sidak_critical_z(VALIDATION_SIGNIFICANCE, len(args.scenes) * 2 * len(CHANNELS))
    measured = {scene: measure_scene(scene, args, z_critical) for scene in args.scenes}
    first = next(iter(measured.values()))
    result = {
        **settings,
        "width": first["width"],
        "height": first["height"],
        "max_depth": {scene: entry["max_depth"] for scene, entry in measured.items()},
        "spp_levels": args.spp,
        "bias_spp": args.bias_spp,
        "cap_spp": args.cap_spp,
        "repeats": args.repeats,
        "seed": args.seed,
        "quality": QUALITY,
        "denoiser_device": denoiser_device(),
        "psnr_definition": "10 log10(1 / MSE) of the clipped, sRGB-encoded images (peak 1)",
        "relative_mse_definition": "bench.error_curves.errors: mean((ours - reference)^2 - reference variance) "
        "/ (reference^2 + 0.01)",
        "atrous": {"viewer_weight_at_spp": {str(spp): viewer_display.filter_weight(spp) for spp in args.spp}},
        "usable_spp": USABLE_SPP,
        "scenes": measured,
        "denoiser_cost": denoiser_cost(args.denoise_size, args.denoise_repeats, args.seed),
    }
    write_result(NAME, result, out=args.out, plot=plot, run=run)
    print_summary(result)
    return 0


def print_summary(result: dict) -> None:
    usable = str(USABLE_SPP)
    for scene, entry in result["scenes"].items():
        levels = "  ".join(
            f"{spp} spp " + " / ".join(f"{entry['psnr'][m][str(spp)]['mean']:.1f}" for m in METHODS)
            for spp in result["spp_levels"]
        )
        print(f"{scene:15s} PSNR dB (raw / a-trous / OIDN / OIDN guided): {levels}")
        picture = entry["usable_picture"]["oidn_guided"]
        raw = (
            f"{picture['raw_seconds']:.2f} s ({picture['raw_spp_needed']:.0f} spp)"
            if picture["raw_seconds"] is not None
            else f"more than {picture['raw_last_seconds']:.2f} s ({picture['raw_last_spp']} spp)"
        )
        converged = entry["bias"]["oidn_guided"]
        print(
            f"{'':15s} usable picture ({picture['target_psnr_db']:.1f} dB, guided OIDN at {usable} spp) in "
            f"{picture['denoised_seconds']:.2f} s instead of {raw}; guides cost "
            f"x{entry['guide_cost']['on_over_off']:.3f} per sample; at {entry['bias']['spp']} spp the largest "
            f"block shift {converged['against_reference']['largest']:.2%} against the reference "
            f"(raw itself {entry['bias']['raw_against_reference']['largest']:.2%}, its block means' noise up to "
            f"{entry['bias']['raw_largest_relative_standard_error']:.2%}), "
            f"{converged['against_raw']['largest']:.2%} against the raw picture"
        )
    for name, cost in result["denoiser_cost"]["costs"].items():
        print(f"denoiser {name}: {cost['seconds_per_megapixel']:.2f} s/MP ({result['denoiser_device']})")


if __name__ == "__main__":
    sys.exit(main())
