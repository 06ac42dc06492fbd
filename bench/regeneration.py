"""Path regeneration measured: for each count of samples per dispatch, how busy the lanes that run
in lockstep are in the kernel's loops, and the time per sample, on the Cornell box and door_ajar.

    python -m bench.regeneration
    python -m bench.regeneration --size 128x128 --spp 16 --counts 1 4 8 16 --repeats 5

Every count renders the same samples from the seed, so its image must equal one sample per
dispatch's bit for bit (checked first). Lanes are then counted (`count_lanes`: subgroup
operations; left out where the adapter has none) and renders of `spp` from the seed timed in
rounds that rotate the order, the speed-up of each count as the median of in-round ratios against
one sample per dispatch, by process CPU time (which other load on a CPU adapter's cores hardly
changes) and by wall time. The count an integrator takes on an adapter type
(`Integrator.dispatch_samples`) is chosen from this. Writes
bench/results/regeneration_<adapter>.json and .png.
"""

from __future__ import annotations

import statistics
import sys

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from bench.timing import fresh_image
from wgputrace import Renderer
from wgputrace.kernels.ray_count import LANE_LOOPS
from wgputrace.render.ray_count import count_lanes
from wgputrace.scenes import BUILTIN_SCENES

SCENES = ("cornell", "door_ajar")
COUNTS = (1, 2, 4, 8, 16, 32)
MAX_DEPTH = 9
# the loops whose lanes are reported (every LANE_LOOPS entry but the kernel's entry, which is the
# subgroup size)
REPORTED_LOOPS = LANE_LOOPS[1:]


def measure_scene(name: str, args, counts: list[int]) -> dict:
    scene = BUILTIN_SCENES[name]()
    width, height = args.size
    renderers = {
        count: Renderer(
            scene,
            width,
            height,
            seed=args.seed,
            max_depth=MAX_DEPTH,
            integrator=args.integrator,
            samples_per_dispatch=count,
        )
        for count in counts
    }
    images = {}
    for count, renderer in renderers.items():
        image, dropped, wall, _ = fresh_image(renderer, args.spp, from_seed=True)  # compiles on lavapipe
        if dropped:
            raise SystemExit(f"{name}, {count} samples per dispatch: {dropped} samples dropped")
        images[count] = image
        log(f"{name}: {count} samples per dispatch, first render {wall:.1f} s")
    differing = [count for count, image in images.items() if not np.array_equal(image, images[counts[0]])]
    if differing:
        raise SystemExit(f"{name}: the images of {differing} samples per dispatch differ from {counts[0]}'s")
    lanes = {}
    for count, renderer in renderers.items():
        if renderer.context.has_subgroups:
            renderer.restart()
            counted = count_lanes(renderer, args.spp)
            if not np.array_equal(renderer.image(), images[count]):
                raise SystemExit(f"{name}, {count} samples per dispatch: the counted render differs from the render")
            lanes[count] = {
                loop: {
                    "utilisation": counted.utilisation(loop),
                    "passes_per_subgroup_sample": counted.passes_per_sample(loop),
                }
                for loop in REPORTED_LOOPS
            }
            lanes[count]["subgroup_size"] = counted.subgroup_size
    wall = {count: [] for count in counts}
    cpu = {count: [] for count in counts}
    for round_index in range(args.repeats):
        shift = round_index % len(counts)
        for count in counts[shift:] + counts[:shift]:
            _, _, seconds, process = fresh_image(renderers[count], args.spp, from_seed=True)
            wall[count].append(seconds)
            cpu[count].append(process)
        log(f"{name}: round {round_index + 1}/{args.repeats}")
    base = counts[0]
    entries = {}
    for count in counts:
        entries[str(count)] = {
            "run_seconds": wall[count],
            "run_process_cpu_seconds": cpu[count],
            "speedup_process_cpu": statistics.median(b / c for b, c in zip(cpu[base], cpu[count], strict=True)),
            "speedup_wall": statistics.median(b / c for b, c in zip(wall[base], wall[count], strict=True)),
            "paths_per_second": width * height * args.spp / statistics.median(wall[count]),
            **({"lanes": lanes[count]} if count in lanes else {}),
        }
    return {"triangles": renderers[base].triangle_count, "counts": entries}


def plot(path, result: dict) -> None:
    """Per scene: lane utilisation of the path and traversal loops, and the speed-up, against the count."""
    scenes = result["scenes"]
    chart = figure(5.0 * len(scenes), 4.2)
    for index, (name, entry) in enumerate(scenes.items(), start=1):
        axes = chart.add_subplot(1, len(scenes), index)
        counts = [int(count) for count in entry["counts"]]
        values = list(entry["counts"].values())
        axes.plot(counts, [v["speedup_process_cpu"] for v in values], "o-", label="speed-up (process CPU)")
        axes.plot(counts, [v["speedup_wall"] for v in values], "o--", label="speed-up (wall)")
        if all("lanes" in v for v in values):
            for loop in ("path", "traversal", "triangle"):
                utilisation = [v["lanes"][loop]["utilisation"] for v in values]
                axes.plot(counts, utilisation, "s:", label=f"{loop} loop: busy lanes")
        axes.set_xscale("log", base=2)
        axes.set_xlabel("samples per dispatch")
        axes.set_title(f"{name} ({entry['triangles']} triangles)", fontsize=10)
        axes.grid(alpha=0.3)
        axes.legend(fontsize=7)
    save_figure(
        chart,
        path,
        result,
        f"path regeneration, {result['integrator']}, {result['width']}x{result['height']}, {result['spp']} spp, "
        f"max depth {result['max_depth']}",
    )


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=(128, 128), spp=32, repeats=5, seed=1)
    parser.add_argument("--counts", type=int, nargs="+", default=list(COUNTS), help="samples per dispatch to compare")
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=sorted(BUILTIN_SCENES))
    parser.add_argument("--integrator", default="mis")
    args = parse(parser, argv, "counts")
    counts = list(dict.fromkeys([1, *args.counts]))
    run = Run()
    scenes = {name: measure_scene(name, args, counts) for name in args.scenes}
    result = {
        "scene": ", ".join(args.scenes),
        "width": args.size[0],
        "height": args.size[1],
        "spp": args.spp,
        "max_depth": MAX_DEPTH,
        "integrator": args.integrator,
        "seed": args.seed,
        "repeats": args.repeats,
        "timing": "Renderer.render(spp) from the seed per count, rounds rotating the order; speed-ups are medians "
        "of in-round ratios against 1 sample per dispatch",
        "lanes": "count_lanes: per pass of a subgroup through a loop, the lanes taking part; utilisation = lanes / "
        "(passes x subgroup size); passes per subgroup and sample are what the subgroup's time follows",
        "scenes": scenes,
    }
    write_result("regeneration", result, out=args.out, plot=plot, run=run)
    for name, entry in scenes.items():
        print(f"{name} ({entry['triangles']} triangles), {args.size[0]}x{args.size[1]}, {args.spp} spp:")
        for count, values in entry["counts"].items():
            lanes = values.get("lanes", {})
            busy = "  ".join(
                f"{loop} {lanes[loop]['utilisation']:.3f} ({lanes[loop]['passes_per_subgroup_sample']:.1f})"
                for loop in REPORTED_LOOPS
                if loop in lanes
            )
            print(
                f"  {count:>3} per dispatch: x{values['speedup_process_cpu']:.3f} CPU, x{values['speedup_wall']:.3f} "
                f"wall, {values['paths_per_second'] / 1e6:.3f} M paths/s; busy lanes (passes): {busy}"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
