"""Frames per second of the viewer in a real window, moving and at rest, at 640x480 and 1280x720.

    python -m bench.viewer_fps
    python -m bench.viewer_fps --sizes 640x480 --seconds 10

The viewer's glfw window (on a virtual X display started for the run where there is no DISPLAY)
on the default scene. Each size: a warm-up, then a moving phase in which the camera turns a little
every frame as a steady mouse drag does (the moving picture, upsampled where the budget asks for
it), then a resting phase at full resolution. Reported per phase: frames per second, median and
90th percentile frame times, the traced resolution, the frames of each upscale factor, and at rest
samples per second and the samples per pixel reached. Writes
bench/results/viewer_fps_<adapter>.json and .png.
"""

from __future__ import annotations

import statistics
import sys
import time
from contextlib import nullcontext
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from wgputrace.app.options import ViewerOptions
from wgputrace.app.pacing import REST_SECONDS
from wgputrace.app.viewer import Viewer
from wgputrace.app.window import create_canvas, has_display
from wgputrace.cli_arguments import parse_size
from wgputrace.scenes import DEFAULT_SCENE
from wgputrace.testing.display import virtual_display
from wgputrace.view.upscale_choice import FACTORS

WARMUP_SECONDS = 4.0
# The camera turns this many pixels' worth of mouse drag per frame while moving, to the right for
# TURN_SECONDS, then back to the left, and so on: the view stays on the scene.
TURN_PIXELS_PER_FRAME = 2.0
TURN_SECONDS = 1.0


def run_size(size: tuple[int, int], seconds: float, target_fps: float) -> dict:
    from rendercanvas.glfw import loop

    canvas = create_canvas(size, f"wgputrace - {DEFAULT_SCENE}")
    viewer = Viewer(canvas, ViewerOptions(size=size, target_fps=target_fps))
    moving_start = WARMUP_SECONDS
    resting_start = moving_start + seconds + REST_SECONDS
    end = resting_start + seconds
    marks: dict[str, int] = {}
    start = time.perf_counter()

    def draw() -> None:
        now = time.perf_counter() - start
        if moving_start <= now < moving_start + seconds:
            marks.setdefault("moving", len(viewer.frames))
            direction = 1.0 if int((now - moving_start) / TURN_SECONDS) % 2 == 0 else -1.0
            viewer.input.look(direction * TURN_PIXELS_PER_FRAME, 0.0)
        elif now >= resting_start:
            marks.setdefault("resting", len(viewer.frames))
        if moving_start + seconds <= now:
            marks.setdefault("moving_end", len(viewer.frames))
        viewer.draw()
        if now >= end:
            canvas.close()

    canvas.request_draw(draw)
    loop.run()
    moving = viewer.frames[marks["moving"] : marks["moving_end"]]
    resting = viewer.frames[marks["resting"] :]
    width, height = size
    samples = (resting[-1].samples_per_pixel - resting[0].samples_per_pixel) * width * height
    resting_seconds = sum(frame.seconds for frame in resting[1:])
    return {
        "size": list(size),
        "moving": phase(moving),
        "resting": {
            **phase(resting),
            "samples_per_second": samples / resting_seconds,
            "samples_per_pixel_reached": resting[-1].samples_per_pixel,
        },
    }


def phase(frames) -> dict:
    seconds = np.array([frame.seconds for frame in frames])
    traced = [frame.traced_size[0] * frame.traced_size[1] for frame in frames]
    median_traced = frames[int(np.argsort(traced)[len(traced) // 2])].traced_size
    return {
        "frames": len(frames),
        "fps": len(frames) / seconds.sum(),
        "median_frame_ms": 1e3 * statistics.median(seconds),
        "p90_frame_ms": 1e3 * float(np.percentile(seconds, 90)),
        "median_trace_ms": 1e3 * statistics.median(frame.trace_seconds for frame in frames),
        "median_traced_size": list(median_traced),
        # the moving picture's upscale factors (FrameRecord.upscale): how many frames took each
        "upscale_frames": {str(f): sum(frame.upscale == f for frame in frames) for f in FACTORS},
        "all_moving": all(frame.moving for frame in frames),
    }


def plot(path: Path, result: dict) -> None:
    chart = figure(7.0, 4.4)
    axes = chart.add_subplot()
    names = [f"{w}x{h}" for w, h in (entry["size"] for entry in result["sizes"])]
    x = np.arange(len(names))
    for offset, key, color in ((-0.2, "moving", "#d08030"), (0.2, "resting", "#3b75af")):
        values = [entry[key]["fps"] for entry in result["sizes"]]
        bars = axes.bar(x + offset, values, width=0.4, color=color, label=key, zorder=2)
        labels = []
        for entry in result["sizes"]:
            traced = entry[key]["median_traced_size"]
            labels.append(f"{entry[key]['fps']:.1f} fps\n{traced[0]}x{traced[1]}")
        axes.bar_label(bars, labels=labels, padding=2, fontsize=8)
    axes.axhline(
        result["target_fps"], color="gray", linestyle="--", linewidth=1, label=f"target {result['target_fps']:g} fps"
    )
    axes.set_xticks(x, names)
    axes.set_ylabel("frames per second (label: traced resolution)")
    axes.set_ylim(0, max(result["target_fps"], *(e["moving"]["fps"] for e in result["sizes"])) * 1.35)
    axes.legend(loc="upper right")
    axes.grid(axis="y", alpha=0.3, zorder=0)
    save_figure(chart, path, result, f"wgputrace viewer, {DEFAULT_SCENE}", dpi=120)


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__)
    parser.add_argument("--sizes", type=parse_size, nargs="+", default=[(640, 480), (1280, 720)])
    parser.add_argument("--seconds", type=float, default=10.0, help="length of each phase (default 10)")
    parser.add_argument("--fps", type=float, default=20.0, help="the viewer's target fps (default 20)")
    args = parse(parser, argv)
    run = Run()
    with nullcontext() if has_display() else virtual_display():
        sizes = []
        for size in args.sizes:
            entry = run_size(size, args.seconds, args.fps)
            sizes.append(entry)
            log(
                f"{size[0]}x{size[1]}: moving {entry['moving']['fps']:.1f} fps (traced "
                f"{'x'.join(map(str, entry['moving']['median_traced_size']))}, frames per upscale "
                f"{entry['moving']['upscale_frames']}), resting {entry['resting']['fps']:.1f} fps, "
                f"{entry['resting']['samples_per_second'] / 1e6:.3f} M samples/s"
            )
        import glfw

        glfw.terminate()  # while the display is still there: glfw's exit handler would talk to it
    result = {
        "scene": DEFAULT_SCENE,
        "width": [size[0] for size in args.sizes],
        "height": [size[1] for size in args.sizes],
        "spp": None,  # as many per frame as fit the frame time: see "sizes"
        "max_depth": ViewerOptions.max_depth,
        "target_fps": args.fps,
        "phase_seconds": args.seconds,
        "warmup_seconds": WARMUP_SECONDS,
        "turn_pixels_per_frame": TURN_PIXELS_PER_FRAME,
        "turn_seconds": TURN_SECONDS,
        "sizes": sizes,
    }
    write_result("viewer_fps", result, out=args.out, plot=plot, run=run)
    return 0


if __name__ == "__main__":
    sys.exit(main())
