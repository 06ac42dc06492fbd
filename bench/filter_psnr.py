"""PSNR of the viewer's picture against the Mitsuba 3 reference, with and without the
pre-convergence filter, at 1, 4, 16 and 64 samples per pixel (default scene).

    python -m bench.filter_psnr
    python -m bench.filter_psnr --repeats 8 --spp 1 4 16 64

The picture is what the viewer shows at rest: the mean of the samples, or the filtered one at the
weight the viewer gives it at that many samples per pixel; a third column shows the filter at full
weight, which the fade gives up for the converged image's sake. PSNR is taken on what a person
sees (clipped to [0, 1], sRGB-encoded, peak 1), over repeats with their own seeds. Without the
test reference a long render of our own stands in, and the results say so. Writes
bench/results/filter_psnr_<adapter>.json, .csv and .png.
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_csv, write_result
from wgputrace import Renderer, default_scene
from wgputrace.scenes import DEFAULT_SCENE
from wgputrace.testing.image_statistics import displayed_psnr
from wgputrace.testing.references import load_reference
from wgputrace.view import display as viewer_display
from wgputrace.view.banded import BandedRenderer

# Without the Mitsuba reference: our own render with this many samples per pixel stands in.
FALLBACK_REFERENCE_SPP = 1024
FALLBACK_SIZE = 128
MAX_DEPTH = 9
VARIANTS = ("unfiltered", "filtered", "full_filter")


def reference_image() -> tuple[np.ndarray, dict]:
    """The Mitsuba reference's mean (H, W, 3) and how it was made, or our own long render."""
    try:
        reference = load_reference(DEFAULT_SCENE)
        return reference.estimate.mean.astype(np.float32), {"kind": "mitsuba", **reference.metadata}
    except FileNotFoundError as missing:
        log(f"{missing}: rendering our own {FALLBACK_REFERENCE_SPP} spp reference")
    renderer = Renderer(default_scene(), FALLBACK_SIZE, FALLBACK_SIZE, seed=1_000_003, max_depth=MAX_DEPTH)
    renderer.render(FALLBACK_REFERENCE_SPP)
    return renderer.image(), {"kind": "wgputrace", "spp": FALLBACK_REFERENCE_SPP, "note": "Mitsuba reference missing"}


def measure(
    reference: np.ndarray, spp_levels: list[int], repeats: int, seed: int
) -> tuple[dict[str, dict[int, list[float]]], dict[str, dict[int, list[float]]]]:
    """PSNR and mean linear radiance of every variant, per sample count, one value per repeat."""
    height, width = reference.shape[:2]
    scene = default_scene()
    renderer = Renderer(scene, width, height, seed=seed, max_depth=MAX_DEPTH)
    banded = BandedRenderer(renderer)
    display = viewer_display.Display(banded)
    settings = {
        "unfiltered": viewer_display.ViewSettings(),
        "filtered": viewer_display.ViewSettings(filter_enabled=True),
        "full_filter": viewer_display.ViewSettings(filter_enabled=True, fade=False),
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
                results[name][spp].append(displayed_psnr(image, reference))
                means[name][spp].append(float(image.mean(dtype=np.float64)))
        levels = (
            f"{spp} spp {results['unfiltered'][spp][-1]:.2f}/{results['filtered'][spp][-1]:.2f} dB"
            for spp in spp_levels
        )
        log(f"repeat {repeat + 1}/{repeats}: {', '.join(levels)}")
    return results, means


def plot(path: Path, result: dict) -> None:
    chart = figure(7.0, 4.6)
    axes = chart.add_subplot()
    levels = result["spp"]
    labels = {
        "unfiltered": "mean of the samples",
        "filtered": f"viewer's filter (fading out at {result['filter']['fade_spp']} spp)",
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
    title = f"pre-convergence filter on {result['scene']} {result['width']}x{result['height']}"
    if "4" in result["gain_db"]:
        title += f": +{result['gain_db']['4']:.2f} dB at 4 spp"
    save_figure(chart, path, result, f"{title}; reference: {result['reference']['kind']}", fontsize=10, dpi=120)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, repeats=8, seed=1)
    parser.add_argument("--spp", type=int, nargs="+", default=[1, 4, 16, 64], help="sample counts (ascending)")
    args = parse(parser, argv)
    if args.spp != sorted(set(args.spp)):
        parser.error(f"--spp must be ascending counts, got {args.spp}")
    run = Run()
    reference, reference_info = reference_image()
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
            key: getattr(viewer_display, f"FILTER_{key.upper()}")
            for key in ("passes", "normal_power", "depth_sigma", "albedo_sigma", "fade_spp")
        }
        | {"weight_at_spp": {str(spp): viewer_display.filter_weight(spp) for spp in args.spp}},
        "psnr": summary,
        "gain_db": gains,
        "mean_radiance_ratio_to_unfiltered": mean_ratio,
        "reference_mean_radiance": float(reference.mean(dtype=np.float64)),
    }
    write_result("filter_psnr", result, out=args.out, plot=plot, run=run)
    rows = [
        {"spp": spp, "filter_weight": f"{viewer_display.filter_weight(spp):.3f}", "gain_db": f"{gains[str(spp)]:.3f}"}
        | {f"psnr_{name}_db": f"{summary[name][str(spp)]['mean']:.3f}" for name in VARIANTS}
        | {"repeats": args.repeats}
        for spp in args.spp
    ]
    write_csv("filter_psnr", rows, list(rows[0]), args.out)
    for spp in args.spp:
        print(
            f"{spp:4d} spp  unfiltered {summary['unfiltered'][str(spp)]['mean']:6.2f} dB  "
            f"filtered {summary['filtered'][str(spp)]['mean']:6.2f} dB (weight {viewer_display.filter_weight(spp):.2f})  "
            f"full filter {summary['full_filter'][str(spp)]['mean']:6.2f} dB  gain {gains[str(spp)]:+.2f} dB  "
            f"mean radiance x{mean_ratio['filtered'][str(spp)]:.4f}"
        )
    print(f"reference: {reference_info['kind']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
