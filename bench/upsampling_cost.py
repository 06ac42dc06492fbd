"""What temporal upsampling costs per frame: `render_frame(upscale=f)` at 2x and 4x against the
full-resolution frame of one sample per pixel, on the Cornell box while the camera pans.

    python -m bench.upsampling_cost
    python -m bench.upsampling_cost --sizes 320x240 640x480 --frames 16 --warm-up 4

Every mode renders the same camera path on its own Renderer, frame by frame in turn (mode after
mode within each frame), so the machine's load falls on all alike. A frame's time is the wall
time of `render_frame`, the picture read back included; the first `--warm-up` frames (pipeline
compiles, the first histories) are discarded, the medians of the rest reported with their ratio to
the full-resolution frame. Before timing, each mode's last frame is checked finite, and its sRGB
PSNR against a `--reference-spp` render of that camera is recorded at the smallest size (the
quality the saved time buys; the reference's own noise lowers every PSNR alike). Writes
bench/results/upsampling_cost_<adapter>.json and .png.

Another benchmark takes a mode from MODES by name: its upscale factor for `render_frame`.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from wgputrace import Camera, Renderer, default_scene
from wgputrace.cli_arguments import parse_size
from wgputrace.scenes import DEFAULT_SCENE
from wgputrace.testing.image_statistics import displayed_psnr

# render_frame's upscale factor of each mode; "full" traces every pixel.
MODES = {"full": 1, "upsampled_2x": 2, "upsampled_4x": 4}
MAX_DEPTH = 9
# The pan: the camera slides right this far per frame (about a pixel at 320x240).
PAN_STEP = 0.004


def pan_camera(frame: int) -> Camera:
    """The default scene's camera slid right by PAN_STEP per frame."""
    return Camera(position=(PAN_STEP * frame, 0.31, -1.2), forward=(0.0, 0.0, 1.0), vfov_degrees=53.13)


def time_frames(size: tuple[int, int], frames: int, seed: int) -> tuple[dict[str, list[float]], dict[str, np.ndarray]]:
    """Seconds of every frame of every mode, and each mode's last picture."""
    width, height = size
    renderers = {mode: Renderer(default_scene(), width, height, seed=seed, max_depth=MAX_DEPTH) for mode in MODES}
    seconds: dict[str, list[float]] = {mode: [] for mode in MODES}
    last: dict[str, np.ndarray] = {}
    for frame in range(frames):
        for mode, renderer in renderers.items():
            start = time.perf_counter()
            last[mode] = renderer.render_frame(pan_camera(frame), spp=1, upscale=MODES[mode])
            seconds[mode].append(time.perf_counter() - start)
        log(
            f"{width}x{height} frame {frame + 1}/{frames}: "
            + ", ".join(f"{m} {s[-1] * 1e3:.0f} ms" for m, s in seconds.items())
        )
    return seconds, last


def plot(path: Path, result: dict) -> None:
    chart = figure(7.0, 4.2)
    axes = chart.add_subplot()
    sizes = list(result["sizes"])
    width = 0.8 / len(MODES)
    for index, mode in enumerate(MODES):
        values = [result["sizes"][size][mode]["median_ms"] for size in sizes]
        positions = [k + (index - (len(MODES) - 1) / 2) * width for k in range(len(sizes))]
        bars = axes.bar(positions, values, width, label=mode.replace("_", " "))
        axes.bar_label(bars, fmt="%.0f", fontsize=8)
    axes.set_xticks(range(len(sizes)), sizes)
    axes.set_ylabel("ms per frame (median)")
    axes.grid(alpha=0.3, axis="y")
    axes.legend()
    save_figure(chart, path, result, f"render_frame on {result['scene']} while panning, 1 sample per traced pixel")


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, seed=1)
    parser.add_argument("--sizes", type=parse_size, nargs="+", default=[(320, 240), (640, 480)], help="WxH sizes")
    parser.add_argument("--frames", type=int, default=16, help="frames per mode and size, warm-up included")
    parser.add_argument("--warm-up", type=int, default=4, help="first frames left out of the medians")
    parser.add_argument("--reference-spp", type=int, default=256, help="samples of the PSNR reference")
    args = parse(parser, argv, "frames", "reference_spp")
    if not 0 <= args.warm_up < args.frames:
        parser.error(f"--warm-up must be from 0 to --frames - 1, got {args.warm_up}")
    run = Run()
    sizes = {}
    psnr = {}
    for number, size in enumerate(args.sizes):
        seconds, last = time_frames(size, args.frames, args.seed)
        for mode, image in last.items():
            if not np.isfinite(image).all():
                raise SystemExit(f"{mode} at {size[0]}x{size[1]}: the last frame is not finite")
        medians = {mode: statistics.median(values[args.warm_up :]) for mode, values in seconds.items()}
        sizes[f"{size[0]}x{size[1]}"] = {
            mode: {
                "median_ms": medians[mode] * 1e3,
                "ratio_to_full": medians[mode] / medians["full"],
                "frame_ms": [value * 1e3 for value in seconds[mode]],
            }
            for mode in MODES
        }
        if number == 0:
            reference = Renderer(default_scene(), *size, seed=args.seed + 1_000_003, max_depth=MAX_DEPTH)
            reference.set_camera(pan_camera(args.frames - 1))
            reference.render(args.reference_spp)
            psnr = {mode: displayed_psnr(image, reference.image()) for mode, image in last.items()}
            psnr["size"] = f"{size[0]}x{size[1]}"
    result = {
        "scene": DEFAULT_SCENE,
        "width": None,
        "height": None,
        "spp": 1,
        "max_depth": MAX_DEPTH,
        "frames": args.frames,
        "warm_up": args.warm_up,
        "pan_step": PAN_STEP,
        "modes": MODES,
        "sizes": sizes,
        "psnr_last_frame_db": psnr,
        "reference_spp": args.reference_spp,
    }
    write_result("upsampling_cost", result, out=args.out, plot=plot, run=run)
    for size, modes in sizes.items():
        print(
            f"{size}: "
            + ", ".join(f"{mode} {v['median_ms']:.1f} ms (x{v['ratio_to_full']:.2f})" for mode, v in modes.items())
        )
    print("last frame PSNR at " + psnr["size"] + ": " + ", ".join(f"{m} {psnr[m]:.2f} dB" for m in MODES))
    return 0


if __name__ == "__main__":
    sys.exit(main())
