"""Many lights in motion at equal time per frame: the moving picture `Renderer.render_frame` makes
(temporal accumulation; `--filtered`: through SVGF, as the viewer shows it) through a fly-through,
traced by next-event estimation with the light table (nee), today's default (mis), ReSTIR's
candidates at each first vertex (restir, as shipped), with each pixel's reservoir kept for the next
frame (restir-t20: the override RESERVOIR_HISTORY_CAP 20; restir-t1 and restir-t4 when named) and
with 3 neighbours' instead (restir-k3), on the street walk (`bench.fly_throughs.STREET`), the
Cornell box and the textured asset under the sunny sky; FLIP, PSNR and instability against each
frame's converged reference (`bench.realtime`'s measures).

    python -m bench.restir_frames                 (about 13 minutes on lavapipe, 2 cores, references made)
    python -m bench.restir_frames --scenes street --filtered --modes restir restir-t1 restir-t20

Each frame's samples are as many as fit the budget (`SampleBudget`, at least one), so the modes
are compared at equal time per frame, the modes taking turns frame by frame (`bench.realtime.run_budget`).
Writes bench/results/restir_frames_<adapter>.json and .png (with --filtered,
restir_frames_filtered_<adapter>), and the last frames beside their references in
restir_frames[_filtered]_frames_<adapter>.png.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.fly_throughs import FLY_THROUGHS, FULL_FRAMES, STREET
from bench.frame_metrics import flip_missing
from bench.frame_references import FrameReferences, default_cache
from bench.provenance import Run
from bench.realtime import plot_pictures, run_budget, summary
from bench.realtime_modes import Mode, Settings, TemporalPlayer
from bench.result_files import record_skip, result_stem, write_result

NAME = "restir_frames"
SIZE = (320, 240)
FRAMES = 30
# the frame budget: 200 ms, which holds one sample of each pixel of the street at 320x240 on lavapipe
BUDGET_SECONDS = 0.2
REFERENCE_SPP = 64
MAX_DEPTH = 5
# eight columns of pictures stay under 2 MB
PICTURES_DPI = 70
FLIES = {"street": STREET, "cornell": FLY_THROUGHS["cornell"], "asset": FLY_THROUGHS["asset"]}


def frame_modes(filtered: bool) -> dict[str, Mode]:
    """The modes by name, their pictures through SVGF's filter where `filtered`."""

    def make(name, label, color, integrator, overrides, default=True) -> Mode:
        def player(fly, settings):
            return TemporalPlayer(
                fly, settings, filtered=filtered, oidn=False, integrator=integrator, overrides=overrides
            )

        return Mode(name, label, color, player, default=default)

    def history_cap(frames: int, color: str, default: bool = False) -> Mode:
        """restir keeping each pixel's reservoir for the next frame, where it counts as at most
        `frames` frames' candidates."""
        overrides = {"RESERVOIR_HISTORY_CAP": frames}
        label = f"ReSTIR + previous frame's reservoirs (cap {frames})"
        return make(f"restir-t{frames}", label, color, "restir", overrides, default)

    return {
        mode.name: mode
        for mode in (
            make("nee", "next-event estimation, light table", "#888888", "nee", {}),
            make("mis", "MIS (today's default)", "#3b75af", "mis", {}),
            make("restir", "ReSTIR candidates (as shipped)", "#d08030", "restir", {}),
            history_cap(20, "#c03030", default=True),
            make("restir-k3", "ReSTIR + 3 neighbours' reservoirs", "#50a050", "restir", {"RESERVOIR_NEIGHBOURS": 3}),
            history_cap(1, "#e0a0a0"),
            history_cap(4, "#a06060"),
        )
    }


MODES = frame_modes(filtered=False)
# The modes run unless --modes names others.
DEFAULT_MODES = [name for name, mode in MODES.items() if mode.default]
# Issue 27's fly-through targets: on the many-light street at least 2x lower FLIP than nee at equal
# time per frame; on the Cornell box no worse than today (mis).
TARGETS = {"street_restir_flip_ratio_over_nee": 2.0, "cornell_restir_flip_ratio_over_mis": 1.0}


def flip_ratio(summaries: dict, scene: str, baseline: str, mode: str = "restir") -> float | None:
    """The baseline's mean FLIP over `mode`'s on `scene` (above 1: `mode` is better)."""
    entry = summaries.get(scene, {})
    if baseline not in entry or mode not in entry:
        return None
    return entry[baseline]["mean_flip"] / entry[mode]["mean_flip"]


def plot(path: Path, result: dict) -> None:
    scenes = list(result["scenes"])
    chart = figure(4.6 * len(scenes), 7.5)
    grid = chart.subplots(2, len(scenes), squeeze=False)
    for column, scene in enumerate(scenes):
        run = result["scenes"][scene]
        axes = grid[0][column]
        for name, entry in run["modes"].items():
            points = [(frame["frame"], frame["flip"]) for frame in entry["frames"]]
            axes.plot(*zip(*points, strict=True), color=MODES[name].color, label=name, linewidth=1)
        axes.set_xlabel("frame")
        axes.set_ylabel("FLIP (lower is better)")
        axes.set_title(f"{scene}, {1e3 * result['budget_seconds']:.0f} ms a frame", fontsize=9)
        axes.grid(alpha=0.3)
        axes = grid[1][column]
        names = list(run["summary"])
        axes.bar(names, [run["summary"][name]["mean_flip"] for name in names], color=[MODES[n].color for n in names])
        axes.set_ylabel("mean FLIP")
        axes.tick_params(axis="x", labelrotation=30, labelsize=7)
        axes.grid(alpha=0.3, axis="y")
    grid[0][0].legend(fontsize=7)
    save_figure(chart, path, result, f"wgputrace: many lights in motion, {result['width']}x{result['height']}")


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__, size=SIZE, seed=1)
    parser.add_argument("--scenes", nargs="+", choices=list(FLIES), default=list(FLIES))
    parser.add_argument("--modes", nargs="+", choices=list(MODES), default=DEFAULT_MODES)
    parser.add_argument("--frames", type=int, default=FRAMES, help=f"frames per fly-through (default {FRAMES})")
    parser.add_argument("--budget", type=float, default=BUDGET_SECONDS, help="seconds per frame (default 0.2)")
    parser.add_argument("--reference-spp", type=int, default=REFERENCE_SPP)
    parser.add_argument("--max-depth", type=int, default=MAX_DEPTH)
    parser.add_argument(
        "--filtered", action="store_true", help="the pictures through SVGF's filter, as the viewer shows them"
    )
    parser.add_argument("--cache", type=Path, default=default_cache(), help="the references' folder")
    args = parse(parser, argv, "frames", "reference_spp", "max_depth")
    if args.frames > FULL_FRAMES:
        parser.error(f"--frames is at most the fly-through's {FULL_FRAMES}")
    width, height = args.size
    settings = {"scene": args.scenes, "width": width, "height": height, "spp": None, "max_depth": args.max_depth}
    missing = flip_missing()
    if missing:
        return record_skip(NAME, settings, missing, args.out)
    run = Run()
    frame_settings = Settings(width, height, args.budget, args.seed, args.max_depth)
    scenes, pictures = {}, {}
    for scene in args.scenes:
        fly = FLIES[scene]
        references = FrameReferences(fly, width, height, args.reference_spp, args.max_depth, args.cache)
        log(f"{scene}: {args.frames} frames at {1e3 * args.budget:.0f} ms, modes {', '.join(args.modes)}")
        measured, pictures[scene] = run_budget(
            fly, references, frame_settings, args.modes, args.frames, frame_modes(args.filtered)
        )
        measured["summary"] = summary(measured, args.budget)
        scenes[scene] = measured
        for mode, entry in measured["summary"].items():
            log(
                f"  {mode:>18}: FLIP {entry['mean_flip']:.4f}, PSNR {entry['mean_psnr']:.2f} dB, {entry['mean_spp']:.2f} spp"
            )
    summaries = {scene: entry["summary"] for scene, entry in scenes.items()}
    measured = {
        "street_restir_flip_ratio_over_nee": flip_ratio(summaries, "street", "nee"),
        "cornell_restir_flip_ratio_over_mis": flip_ratio(summaries, "cornell", "mis"),
    }
    result = {
        **settings,
        "frames": args.frames,
        "filtered": args.filtered,
        "budget_seconds": args.budget,
        "reference_spp": args.reference_spp,
        "modes": args.modes,
        "mode_labels": {mode: MODES[mode].label for mode in args.modes},
        "targets": TARGETS,
        "measured": measured,
        "met": {key: value is not None and value >= TARGETS[key] for key, value in measured.items()},
        "flip_ratios": {
            scene: {
                f"{baseline}_over_{mode}": flip_ratio(summaries, scene, baseline, mode)
                for mode in args.modes
                for baseline in ("nee", "mis")
            }
            for scene in scenes
        },
        "scenes": scenes,
    }
    name = f"{NAME}_filtered" if args.filtered else NAME
    paths = write_result(name, result, out=args.out, plot=plot, run=run)
    # the last frames, laid out as bench.realtime lays out its runs
    written = json.loads(paths["json"].read_text())
    runs = {scene: {"runs": [entry]} for scene, entry in scenes.items()}
    frames_png = result_stem(f"{name}_frames", args.out).with_suffix(".png")
    plot_pictures(frames_png, written | {"scenes": runs}, pictures, dpi=PICTURES_DPI)
    for key, value in measured.items():
        print(f"{key}: {'-' if value is None else f'{value:.3g}'} (target {TARGETS[key]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
