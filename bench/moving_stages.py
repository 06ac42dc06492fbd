"""Where a moving frame's time goes: `render_frame(spp=1, filtered=True, upscale=f)` through a
fly-through of `bench.realtime`, each stage waited for and timed on its own.

    python -m bench.moving_stages
    python -m bench.moving_stages --scenes cornell asset moving --factors 1 4 --size 320x240 --frames 16

The stages, in the order a frame runs them: tracing (`Renderer.render` at full resolution,
`TemporalUpsampling.trace` upsampled), rebuilding the history (`add_frame` of
`TemporalAccumulation` or `TemporalUpsampling`), the variance-guided filter
(`VarianceGuidedFilter.filter`), temporal antialiasing (`TemporalAntialiasing.resolve`, upsampled
only) and reading the picture back (`picture_image`). Each is wrapped for the run so that the
adapter finishes all work before it starts and after it ends: a stage's time is its own, the
Python that encodes it included, and the frame's (`frame`) is the sum plus what lies between. The
waits keep the adapter from overlapping one stage with the next, so the frame takes somewhat longer
than without them. The first `--warm-up` frames (pipeline compiles, young histories) are left out
of the medians. Writes bench/results/moving_stages_<adapter>.json and .png.
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.fly_throughs import FLY_THROUGHS
from bench.provenance import Run
from bench.result_files import write_result
from wgputrace import Renderer
from wgputrace.app.options import ViewerOptions
from wgputrace.render import renderer as renderer_module
from wgputrace.render.svgf_filter import VarianceGuidedFilter
from wgputrace.render.temporal_accumulation import TemporalAccumulation
from wgputrace.render.temporal_antialiasing import TemporalAntialiasing
from wgputrace.render.temporal_upsampling import UPSCALE_FACTORS, TemporalUpsampling

# (stage, the object whose attribute is wrapped, the attribute), by factor kind; read-back is the
# renderer module's function, as render_frame calls it
FULL_RESOLUTION_STAGES = (
    ("tracing", Renderer, "render"),
    ("rebuilding", TemporalAccumulation, "add_frame"),
    ("filtering", VarianceGuidedFilter, "filter"),
    ("read-back", renderer_module, "picture_image"),
)
UPSAMPLED_STAGES = (
    ("tracing", TemporalUpsampling, "trace"),
    ("rebuilding", TemporalUpsampling, "add_frame"),
    ("filtering", VarianceGuidedFilter, "filter"),
    ("antialiasing", TemporalAntialiasing, "resolve"),
    ("read-back", renderer_module, "picture_image"),
)
STAGES = ("tracing", "rebuilding", "filtering", "antialiasing", "read-back")


@contextmanager
def timed_stages(renderer: Renderer, factor: int, seconds: dict[str, list[float]]) -> Iterator[None]:
    """While inside, every stage of `renderer`'s frames at `factor` appends its seconds to
    `seconds[stage]`, the adapter finished before and after it."""
    stages = FULL_RESOLUTION_STAGES if factor == 1 else UPSAMPLED_STAGES
    originals = [(owner, name, getattr(owner, name)) for _, owner, name in stages]

    def waited(stage: str, function: Callable) -> Callable:
        def run(*args, **kwargs):
            renderer.context.finish()
            start = time.perf_counter()
            result = function(*args, **kwargs)
            renderer.context.finish()
            seconds[stage].append(time.perf_counter() - start)
            return result

        return run

    for (stage, owner, name), (_, _, function) in zip(stages, originals, strict=True):
        setattr(owner, name, waited(stage, function))
    try:
        yield
    finally:
        for owner, name, function in originals:
            setattr(owner, name, function)


def time_fly_through(scene: str, factor: int, size: tuple[int, int], frames: int, seed: int) -> dict[str, list[float]]:
    """Seconds of each stage and of the whole frame (`frame`), frame by frame, through `frames`
    poses of fly-through `scene` at `factor`."""
    fly = FLY_THROUGHS[scene]
    built = fly.build()
    fly.pose(built, 0)
    renderer = Renderer(built, *size, seed=seed, max_depth=ViewerOptions.max_depth)
    seconds: dict[str, list[float]] = {stage: [] for stage in (*STAGES, "frame")}
    with timed_stages(renderer, factor, seconds):
        for frame in range(frames):
            fly.pose(built, frame)
            start = time.perf_counter()
            renderer.render_frame(spp=1, filtered=True, upscale=factor)
            seconds["frame"].append(time.perf_counter() - start)
    return seconds


def plot(path, result: dict) -> None:
    chart = figure(8.0, 4.2)
    axes = chart.add_subplot()
    labels, bottoms = [], []
    runs = [(scene, factor, entry) for scene, factors in result["scenes"].items() for factor, entry in factors.items()]
    for scene, factor, _ in runs:
        labels.append(f"{scene}\n{factor}x")
        bottoms.append(0.0)
    for stage in STAGES:
        values = [entry["median_ms"].get(stage, 0.0) for _, _, entry in runs]
        axes.bar(range(len(runs)), values, 0.6, bottom=bottoms, label=stage)
        bottoms = [bottom + value for bottom, value in zip(bottoms, values, strict=True)]
    axes.set_xticks(range(len(runs)), labels, fontsize=8)
    axes.set_ylabel("ms per frame (median of each stage)")
    axes.grid(alpha=0.3, axis="y")
    axes.legend(fontsize=8)
    save_figure(
        chart, path, result, f"render_frame(filtered=True) at {result['width']}x{result['height']}, stage by stage"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(320, 240), seed=1)
    parser.add_argument("--scenes", nargs="+", choices=sorted(FLY_THROUGHS), default=sorted(FLY_THROUGHS))
    parser.add_argument(
        "--factors", type=int, nargs="+", choices=(1, *UPSCALE_FACTORS), default=[1, 4], help="upscale factors"
    )
    parser.add_argument("--frames", type=int, default=16, help="frames per scene and factor, warm-up included")
    parser.add_argument("--warm-up", type=int, default=4, help="first frames left out of the medians")
    args = parse(parser, argv, "frames")
    if not 0 <= args.warm_up < args.frames:
        parser.error(f"--warm-up must be from 0 to --frames - 1, got {args.warm_up}")
    run = Run()
    scenes: dict[str, dict[str, dict]] = {}
    for scene in args.scenes:
        for factor in args.factors:
            seconds = time_fly_through(scene, factor, args.size, args.frames, args.seed)
            medians = {
                stage: 1e3 * statistics.median(values[args.warm_up :]) for stage, values in seconds.items() if values
            }
            scenes.setdefault(scene, {})[str(factor)] = {
                "median_ms": medians,
                "frame_ms": [1e3 * value for value in seconds["frame"]],
            }
            log(f"{scene} {factor}x: " + ", ".join(f"{stage} {ms:.1f} ms" for stage, ms in medians.items()))
    width, height = args.size
    result = {
        "scene": ", ".join(args.scenes),
        "width": width,
        "height": height,
        "spp": 1,
        "max_depth": ViewerOptions.max_depth,
        "frames": args.frames,
        "warm_up": args.warm_up,
        "scenes": scenes,
    }
    write_result("moving_stages", result, out=args.out, plot=plot, run=run)
    for scene, factors in scenes.items():
        for factor, entry in factors.items():
            print(f"{scene} {factor}x: " + ", ".join(f"{s} {ms:.1f} ms" for s, ms in entry["median_ms"].items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
