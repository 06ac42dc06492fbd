"""PSNR of the viewer's picture against the Mitsuba 3 reference, with and without the
pre-convergence filter, at 1, 4, 16 and 64 samples per pixel (default scene).

    python bench/filter_psnr.py               (or: python -m bench.filter_psnr)
    python bench/filter_psnr.py --repeats 8 --spp 1 4 16 64

The picture is what the viewer shows at rest: the mean of the samples (through its GPU resolve),
or the filtered one (wgputrace/render/display.py) at the weight the viewer gives it at that many
samples per pixel; a third column shows the filter at full weight, which the fade gives up for
the converged image's sake. PSNR is taken on what a person sees: linear radiance clipped to
[0, 1], sRGB-encoded, peak 1. Each repeat renders with its own seed; the mean and spread over
repeats are reported. The reference is tests/references/cornell.npz (scripts/make_references.py);
without it, a long render of our own stands in, and the results say so.
Writes bench/results/filter_psnr_<adapter>.json, .csv and .png.
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.common import RESULTS_DIR, load_average, result_stem, write_result  # noqa: E402
from wgputrace import Renderer, default_scene  # noqa: E402
from wgputrace.image_io import linear_to_srgb  # noqa: E402
from wgputrace.render.display import (  # noqa: E402
    FILTER_ALBEDO_SIGMA,
    FILTER_DEPTH_SIGMA,
    FILTER_FADE_SPP,
    FILTER_NORMAL_POWER,
    FILTER_PASSES,
    Display,
    ViewSettings,
    filter_weight,
)
from wgputrace.render.progressive import BandedRenderer  # noqa: E402
from wgputrace.scenes import DEFAULT_SCENE  # noqa: E402

REFERENCE = Path(__file__).resolve().parent.parent / "tests" / "references" / f"{DEFAULT_SCENE}.npz"
# Without the Mitsuba reference: our own render with this many samples per pixel stands in.
FALLBACK_REFERENCE_SPP = 1024
FALLBACK_SIZE = 128
MAX_DEPTH = 9
VARIANTS = ("unfiltered", "filtered", "full_filter")


def load_reference(size: int | None) -> tuple[np.ndarray, dict]:
    """The Mitsuba reference's mean (H, W, 3) and how it was made, or our own long render."""
    if REFERENCE.is_file():
        with np.load(REFERENCE) as data:
            metadata = json.loads(str(data["metadata"]))
            mean = data["mean"].astype(np.float32)
        return mean, {"kind": "mitsuba", "path": str(REFERENCE.relative_to(REFERENCE.parents[2])), **metadata}
    side = size or FALLBACK_SIZE
    print(f"{REFERENCE} not found: rendering our own {FALLBACK_REFERENCE_SPP} spp reference", file=sys.stderr)
    renderer = Renderer(default_scene(), side, side, seed=1_000_003, max_depth=MAX_DEPTH)
    renderer.render(FALLBACK_REFERENCE_SPP)
    return renderer.image(), {"kind": "wgputrace", "spp": FALLBACK_REFERENCE_SPP, "note": "Mitsuba reference missing"}


def psnr(image: np.ndarray, reference: np.ndarray) -> float:
    """On the displayed values: clipped to [0, 1] and sRGB-encoded, peak 1."""
    shown, expected = (linear_to_srgb(x.astype(np.float64)) for x in (image, reference))
    return float(10.0 * np.log10(1.0 / np.mean((shown - expected) ** 2)))


def measure(
    reference: np.ndarray, spp_levels: list[int], repeats: int, seed: int
) -> tuple[dict[str, dict[int, list[float]]], dict[str, dict[int, list[float]]]]:
    """PSNR and mean linear radiance of every variant, per sample count, one value per repeat."""
    height, width = reference.shape[:2]
    scene = default_scene()
    renderer = Renderer(scene, width, height, seed=seed, max_depth=MAX_DEPTH)
    banded = BandedRenderer(renderer)
    display = Display(banded)
    settings = {
        "unfiltered": ViewSettings(),
        "filtered": ViewSettings(filter_enabled=True),
        "full_filter": ViewSettings(filter_enabled=True, fade=False),
    }
    results: dict[str, dict[int, list[float]]] = {name: {spp: [] for spp in spp_levels} for name in VARIANTS}
    means: dict[str, dict[int, list[float]]] = {name: {spp: [] for spp in spp_levels} for name in VARIANTS}
    for repeat in range(repeats):
        # the random streams go on from repeat to repeat: each repeat's samples are new ones
        banded.restart(scene.camera)
        display.camera_changed()
        for spp in spp_levels:
            banded.add_passes(spp - banded.samples_per_pixel)
            for name, setting in settings.items():
                display.render(setting)
                image = display.read_image()
                results[name][spp].append(psnr(image, reference))
                means[name][spp].append(float(image.mean(dtype=np.float64)))
        print(
            f"repeat {repeat + 1}/{repeats}: "
            + ", ".join(
                f"{spp} spp {results['unfiltered'][spp][-1]:.2f}/{results['filtered'][spp][-1]:.2f} dB"
                for spp in spp_levels
            ),
            file=sys.stderr,
            flush=True,
        )
    return results, means


def plot(path: Path, result: dict) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7.0, 4.6))
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    levels = result["spp"]
    labels = {
        "unfiltered": "mean of the samples",
        "filtered": f"viewer's filter (fading out at {FILTER_FADE_SPP} spp)",
        "full_filter": "filter at full weight",
    }
    for name, style in zip(VARIANTS, ("o-", "s-", "^--"), strict=True):
        means = [result["psnr"][name][str(spp)]["mean"] for spp in levels]
        spread = [result["psnr"][name][str(spp)]["stdev"] for spp in levels]
        axes.errorbar(levels, means, yerr=spread, fmt=style, capsize=3, label=labels[name])
    axes.set_xscale("log", base=2)
    axes.set_xticks(levels, [str(spp) for spp in levels])
    axes.set_xlabel("samples per pixel")
    axes.set_ylabel(f"PSNR (dB, displayed sRGB), mean of {result['repeats']} seeds")
    axes.grid(alpha=0.3)
    axes.legend(loc="lower right")
    gain = result["gain_db"][str(4)] if "4" in result["gain_db"] else None
    reference = result["reference"]
    title = f"pre-convergence filter on {result['scene']} {result['width']}x{result['height']}"
    if gain is not None:
        title += f": +{gain:.2f} dB at 4 spp"
    figure.suptitle(
        f"{title}\nreference: {reference['kind']}, {result['adapter']['adapter']}, rev {result['git_revision']}",
        fontsize=10,
    )
    figure.tight_layout()
    figure.savefig(path, dpi=120)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, nargs="+", default=[1, 4, 16, 64], help="sample counts (ascending)")
    parser.add_argument("--repeats", type=int, default=8, help="seeds per sample count (default 8)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, default=RESULTS_DIR)
    args = parser.parse_args(argv)
    if args.spp != sorted(set(args.spp)) or args.spp[0] < 1:
        parser.error(f"--spp must be ascending positive counts, got {args.spp}")
    started, load_before = time.perf_counter(), load_average()
    reference, reference_info = load_reference(None)
    height, width = reference.shape[:2]
    results, means = measure(reference, args.spp, args.repeats, args.seed)
    summary = {
        name: {
            str(spp): {
                "mean": statistics.fmean(values),
                "stdev": statistics.stdev(values) if len(values) > 1 else 0.0,
                "runs": values,
            }
            for spp, values in per_spp.items()
        }
        for name, per_spp in results.items()
    }
    gains = {
        str(spp): summary["filtered"][str(spp)]["mean"] - summary["unfiltered"][str(spp)]["mean"] for spp in args.spp
    }
    # energy: the filter's normalized weights should keep the picture's mean radiance
    mean_ratio = {
        name: {
            str(spp): statistics.fmean(f / u for f, u in zip(means[name][spp], means["unfiltered"][spp], strict=True))
            for spp in args.spp
        }
        for name in ("filtered", "full_filter")
    }
    result = {
        "load_average_before_after": [load_before, load_average()],
        "scene": DEFAULT_SCENE,
        "width": width,
        "height": height,
        "max_depth": MAX_DEPTH,
        "spp": args.spp,
        "repeats": args.repeats,
        "seed": args.seed,
        "reference": reference_info,
        "psnr_definition": "10 log10(1 / MSE) of the clipped, sRGB-encoded images (peak 1)",
        "filter": {
            "passes": FILTER_PASSES,
            "normal_power": FILTER_NORMAL_POWER,
            "depth_sigma": FILTER_DEPTH_SIGMA,
            "albedo_sigma": FILTER_ALBEDO_SIGMA,
            "fade_spp": FILTER_FADE_SPP,
            "weight_at_spp": {str(spp): filter_weight(spp) for spp in args.spp},
        },
        "psnr": summary,
        "gain_db": gains,
        "mean_radiance_ratio_to_unfiltered": mean_ratio,
        "reference_mean_radiance": float(reference.mean(dtype=np.float64)),
        "wall_seconds": time.perf_counter() - started,
    }
    paths = write_result("filter_psnr", result, out=args.out, plot=plot)
    with open(result_stem("filter_psnr", args.out).with_suffix(".csv"), "w", newline="") as file:
        writer = csv.writer(file)
        writer.writerow(["spp", "filter_weight", *(f"psnr_{name}_db" for name in VARIANTS), "gain_db", "repeats"])
        for spp in args.spp:
            means = [f"{summary[name][str(spp)]['mean']:.3f}" for name in VARIANTS]
            writer.writerow([spp, f"{filter_weight(spp):.3f}", *means, f"{gains[str(spp)]:.3f}", args.repeats])
    for spp in args.spp:
        print(
            f"{spp:4d} spp  unfiltered {summary['unfiltered'][str(spp)]['mean']:6.2f} dB  "
            f"filtered {summary['filtered'][str(spp)]['mean']:6.2f} dB (weight {filter_weight(spp):.2f})  "
            f"full filter {summary['full_filter'][str(spp)]['mean']:6.2f} dB  gain {gains[str(spp)]:+.2f} dB  "
            f"mean radiance x{mean_ratio['filtered'][str(spp)]:.4f}"
        )
    print(f"reference: {reference_info['kind']}; wrote {paths['json']}, .csv, .png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
