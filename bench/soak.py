"""Soak: the viewer in a real window for minutes of scene edits, bad files, resizes and key presses,
and the library through thousands of render/edit cycles; memory and GPU allocations stay flat.

    python -m bench --only soak                  (about 10 minutes of viewer plus the 10,000 cycles)
    python -m bench.soak --minutes 1 --cycles 500

Not part of the default `python -m bench` run: it measures staying power, not speed. The viewer
(`soak_viewer`) gets one action every ACTION_SECONDS and must reload every rewrite, report every
broken file, print no traceback and exit cleanly; the library (`soak_library`) renders one sample
per edit and every image must be finite. Memory is read as it goes; `memory_trend` fits its slope
after the first WARMUP_FRACTION of the run against FLAT_GROWTH_MIB, and a process passing
--memory-cap-mib is stopped, a failure. Writes bench/results/soak_<adapter>.json and .png.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import time
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bench.charts import figure, save_figure
from bench.command_line import argument_parser, log, parse
from bench.provenance import Run
from bench.result_files import write_result
from wgputrace import Renderer, default_scene
from wgputrace.app.window import has_display
from wgputrace.testing.display import virtual_display

SEED = 20261201
# The first part of a run is left out of the slope: kernels compile, caches and the allocator fill.
WARMUP_FRACTION = 0.2
# Memory counts as flat when the fitted line grows less than this over the measured part of a run.
# A leaked 32x32 image per library cycle would be ~160 MiB over 10,000 cycles; the allocator's own
# drift is a few MiB.
FLAT_GROWTH_MIB = 8.0
# A soaked process whose resident memory passes this is stopped (and the run fails): a leak must
# not take the machine, and its other work, down with it.
MEMORY_CAP_MIB = 3072

VIEWER_SIZES = ((320, 240), (400, 300))
ACTION_SECONDS = 3.0
SAMPLE_SECONDS = 1.0
EXIT_SECONDS = 30.0
# Keys pressed in turn (X keysym names); Space twice, so sampling never stays paused.
KEYS = ("2", "3", "1", "n", "b", "bracketright", "Tab", "space", "space", "plus", "minus", "p", "f", "r", "5", "1")
MOVE_KEY, MOVE_SECONDS = "w", 0.3
ACTIONS = ("edit", "key", "resize", "broken file", "key", "move")

CYCLE_SIZE = (32, 32)
SAMPLE_CYCLES = 50
BOX_SHIFT = 0.05  # box1 moves up to this far from where the scene puts it, on each axis
EDITED_MATERIAL = "white"
MOVED_SHAPE = "box1"

SCENE_FILE = """import numpy as np
import wgputrace as wt


def scene():
    scene = wt.default_scene()
    next(m for m in scene.materials if m.name == "red").color = {color}
    box = scene.shape("box1")
    shift = np.eye(4)
    shift[:3, 3] = {shift}
    box.transform = shift @ box.transform
    return scene
"""
# A shape without a material: the loader names the line, the viewer keeps the scene it had.
BROKEN_FILE = "import wgputrace as wt\n\n\ndef scene():\n    return wt.Scene([wt.make_plane((0, 0, 2), (0, 0, 0), (1, 1), None)])\n"


def resident_kib(pid: int | str = "self") -> int:
    """VmRSS of a process in KiB (psutil is not a dependency)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise RuntimeError(f"/proc/{pid}/status has no VmRSS line")


def memory_trend(x: list[float], kib: list[int]) -> dict:
    """Least-squares slope of memory (KiB) against x over the samples after the warm-up, and the
    fitted growth in MiB over that span."""
    x, kib = np.asarray(x, np.float64), np.asarray(kib, np.float64)
    keep = x >= x[-1] * WARMUP_FRACTION
    slope = float(np.polyfit(x[keep], kib[keep], 1)[0]) if keep.sum() >= 2 else 0.0
    growth = float(slope * (x[keep][-1] - x[keep][0]) / 1024) if keep.any() else 0.0
    return {
        "slope_kib_per_unit": slope,
        "fitted_growth_mib": growth,
        "measured_from": float(x[keep][0]) if keep.any() else None,
        "first_last_kib": [int(kib[keep][0]), int(kib[-1])] if keep.any() else None,
        "flat": bool(abs(growth) < FLAT_GROWTH_MIB),
    }


# -- the viewer -------------------------------------------------------------------------------------


@dataclass
class ConsoleCount:
    """What the viewer's console said: reloads, reported load failures, tracebacks."""

    reloads: int = 0
    failures_reported: int = 0
    tracebacks: list[str] = field(default_factory=list)

    def read(self, app) -> None:
        while not app.lines.empty():
            line = app.lines.get()
            app.log.append(line)
            self.reloads += "changed, reloading" in line
            self.failures_reported += "scene not loaded" in line
            if "Traceback" in line or re.search(r"\bException\b", line):
                self.tracebacks.append(line)


def recorded_lines(lines: list[str], workdir: Path) -> list[str]:
    """Console lines as the result records them: the scene's temporary folder as WORKDIR, no folder of this machine."""
    return [line.replace(str(workdir), "WORKDIR") for line in lines]


def scene_text(rng: np.random.Generator) -> str:
    color = tuple(round(float(c), 3) for c in rng.uniform(0.1, 0.9, 3))
    shift = [round(float(s), 3) for s in rng.uniform(-BOX_SHIFT, BOX_SHIFT, 3)]
    return SCENE_FILE.format(color=color, shift=shift)


def rewrite(path: Path, text: str, version: int) -> None:
    """Write `text` with a modification time of its own (file systems with coarse times would
    otherwise hide a rewrite within the same second)."""
    path.write_text(text)
    stamp = time.time() + version * 1e-3
    os.utime(path, (stamp, stamp))


def soak_viewer(minutes: float, workdir: Path, cap_kib: int) -> dict:
    """`python app.py SCENE.py` in its own process for `minutes`, one of ACTIONS every ACTION_SECONDS
    in turn (rewrite the scene, press a key, resize, write a broken file, move), its resident memory read
    every SAMPLE_SECONDS; it exits on Escape at the end."""
    from wgputrace.testing.running_app import START_SECONDS, RunningApp
    from wgputrace.testing.xdriver import XDriver

    rng = np.random.default_rng(SEED)
    path = workdir / "soak_scene.py"
    path.write_text(scene_text(rng))
    size = VIEWER_SIZES[0]
    app = RunningApp([str(path), "--size", f"{size[0]}x{size[1]}", "--screenshots", str(workdir)], workdir)
    console = ConsoleCount()
    counts = dict.fromkeys(ACTIONS, 0)
    samples: list[tuple[float, int]] = []
    over_cap = None
    try:
        app.wait_for(r"showing .* window", START_SECONDS)
        driver = XDriver(os.environ["DISPLAY"])
        window = driver.find_window(f"wgputrace - {path}", START_SECONDS)
        driver.pointer_to(window, 10, 10)  # no window manager: the pointer gives the keyboard
        start = time.monotonic()
        next_action, action, version = start, 0, 0
        while (now := time.monotonic()) - start < minutes * 60:
            if app.process.poll() is not None:
                break
            samples.append((now - start, resident_kib(app.process.pid)))
            if samples[-1][1] > cap_kib:
                over_cap = samples[-1]
                break
            if now >= next_action:
                kind = ACTIONS[action % len(ACTIONS)]
                version += 1
                if kind == "edit":
                    rewrite(path, scene_text(rng), version)
                elif kind == "broken file":
                    rewrite(path, BROKEN_FILE, version)
                elif kind == "resize":
                    size = VIEWER_SIZES[(VIEWER_SIZES.index(size) + 1) % len(VIEWER_SIZES)]
                    driver.resize(window, *size)
                elif kind == "move":
                    driver.hold(MOVE_KEY, MOVE_SECONDS)
                else:
                    driver.tap(KEYS[counts["key"] % len(KEYS)])
                counts[kind] += 1
                action += 1
                next_action += ACTION_SECONDS
            console.read(app)
            time.sleep(SAMPLE_SECONDS)
        crashed = app.process.poll()
        if crashed is None:
            driver.tap("Escape")
            try:
                exit_code = app.process.wait(EXIT_SECONDS)
            except Exception:  # still running: stop() below ends it
                exit_code = None
        else:
            exit_code = crashed
        driver.close()
    finally:
        app.stop()
    # the last lines come after the pipe closes
    time.sleep(0.5)
    console.read(app)
    seconds = [t for t, _ in samples]
    kib = [k for _, k in samples]
    rewrites = counts["edit"] + counts["broken file"]
    failures = []
    if over_cap is not None:
        failures.append(
            f"stopped at {over_cap[0] / 60:.2f} min: resident memory {over_cap[1] / 1024:.0f} MiB > the cap"
        )
    if exit_code != 0:
        failures.append(f"the viewer exited with {exit_code} (expected 0 after Escape)")
    if console.tracebacks:
        failures.append(f"{len(console.tracebacks)} tracebacks on the viewer's console")
    if console.reloads < rewrites:
        failures.append(f"{rewrites} rewrites of the scene file, {console.reloads} reloads")
    if console.failures_reported < counts["broken file"]:
        failures.append(f"{counts['broken file']} broken files, {console.failures_reported} reported")
    trend = memory_trend([s / 60 for s in seconds], kib)
    return {
        "minutes": minutes,
        "seconds_run": seconds[-1] if seconds else 0.0,
        "sizes": [list(s) for s in VIEWER_SIZES],
        "actions": counts,
        "reloads": console.reloads,
        "failures_reported": console.failures_reported,
        "tracebacks": recorded_lines(console.tracebacks[:20], workdir),
        "exit_code": exit_code,
        "stopped_over_memory_cap": over_cap is not None,
        "rss_kib": {"seconds": seconds, "kib": kib},
        "rss_trend": {**trend, "unit": "minute"},
        "failures": failures,
        "console_tail": recorded_lines(app.log[-40:], workdir),
    }


# -- the library ------------------------------------------------------------------------------------


def gpu_objects() -> dict:
    """Live wgpu buffers and textures: count and bytes, as wgpu-py's object_counts tracks them."""
    import wgpu

    counts = wgpu.diagnostics.object_counts.get_dict()
    return {
        f"{kind.lower()}_{key}": counts.get(kind, {}).get(name, 0)
        for kind in ("Buffer", "Texture")
        for key, name in (("count", "count"), ("bytes", "resource_mem"))
    }


def soak_library(cycles: int, cap_kib: int) -> dict:
    """One Renderer through `cycles` edits of one sample per pixel each, alternately a material's
    colour and a box moved (a refit, or a rebuild where the refit degraded); this process's memory
    and the live wgpu buffers and textures every SAMPLE_CYCLES cycles."""
    rng = np.random.default_rng(SEED)
    scene = default_scene()
    material = next(m for m in scene.materials if m.name == EDITED_MATERIAL)
    box = scene.shape(MOVED_SHAPE)
    placed = box.transform.copy()
    renderer = Renderer(scene, *CYCLE_SIZE, seed=1)
    rows, nonfinite_images, exception = [], [], None
    start = time.perf_counter()
    for cycle in range(cycles):
        try:
            if cycle % 2 == 0:
                material.color = tuple(rng.uniform(0.1, 0.9, 3))
            else:
                shift = np.eye(4)
                shift[:3, 3] = rng.uniform(-BOX_SHIFT, BOX_SHIFT, 3)
                box.transform = shift @ placed
            renderer.render(1)
            image = renderer.image()
        except Exception as error:  # the soak's finding: recorded, and the cycles stop
            exception = {"cycle": cycle, "error": f"{type(error).__name__}: {error}"}
            break
        if not np.isfinite(image).all():
            nonfinite_images.append(cycle)
        if cycle % SAMPLE_CYCLES == 0 or cycle == cycles - 1:
            rows.append(
                {"cycle": cycle, "seconds": time.perf_counter() - start, "rss_kib": resident_kib(), **gpu_objects()}
            )
            if cycle % (SAMPLE_CYCLES * 20) == 0:
                log(
                    f"library cycle {cycle:,}: rss {rows[-1]['rss_kib'] / 1024:.1f} MiB, {rows[-1]['buffer_count']} buffers"
                )
            if rows[-1]["rss_kib"] > cap_kib:
                break
    done = cycle + 1 if exception is None else cycle
    measured = [row for row in rows if row["cycle"] >= rows[-1]["cycle"] * WARMUP_FRACTION]
    gpu_growth = {
        key: measured[-1][key] - measured[0][key]
        for key in ("buffer_count", "buffer_bytes", "texture_count", "texture_bytes")
    }
    failures = []
    if rows and rows[-1]["rss_kib"] > cap_kib:
        failures.append(
            f"stopped at cycle {rows[-1]['cycle']:,}: resident memory {rows[-1]['rss_kib'] / 1024:.0f} MiB > the cap"
        )
    if exception:
        failures.append(f"cycle {exception['cycle']}: {exception['error']}")
    if nonfinite_images:
        failures.append(
            f"{len(nonfinite_images)} images held NaN or infinite pixels (first at cycle {nonfinite_images[0]})"
        )
    return {
        "cycles": cycles,
        "cycles_done": done,
        "size": list(CYCLE_SIZE),
        "edits": f"{EDITED_MATERIAL} material colour and {MOVED_SHAPE} moved (up to {BOX_SHIFT} per axis), alternately",
        "seconds": time.perf_counter() - start,
        "samples": rows,
        "rss_trend": {
            **memory_trend([row["cycle"] for row in rows], [row["rss_kib"] for row in rows]),
            "unit": "cycle",
        },
        "gpu_growth_after_warmup": gpu_growth,
        "nonfinite_images": nonfinite_images[:100],
        "nonfinite_samples": renderer.nonfinite_samples,
        "exception": exception,
        "failures": failures,
    }


# -- result -----------------------------------------------------------------------------------------


def plot(path: Path, result: dict) -> None:
    chart = figure(10.0, 4.2)
    viewer_axes, library_axes = chart.add_subplot(1, 2, 1), chart.add_subplot(1, 2, 2)
    viewer = result["viewer"]
    if viewer is not None:
        minutes = np.array(viewer["rss_kib"]["seconds"]) / 60
        viewer_axes.plot(minutes, np.array(viewer["rss_kib"]["kib"]) / 1024, color="#3b75af", linewidth=1)
        trend = viewer["rss_trend"]
        viewer_axes.set_title(
            f"viewer: {trend['slope_kib_per_unit'] / 1024:+.2f} MiB/min after warm-up\n"
            f"{sum(viewer['actions'].values())} actions, {viewer['reloads']} reloads",
            fontsize=9,
        )
    viewer_axes.set_xlabel("minutes")
    viewer_axes.set_ylabel("resident memory (MiB)")
    library = result["library"]
    cycles = [row["cycle"] for row in library["samples"]]
    (rss,) = library_axes.plot(
        cycles, [row["rss_kib"] / 1024 for row in library["samples"]], color="#3b75af", label="host RSS"
    )
    library_axes.set_xlabel("render/edit cycles")
    library_axes.set_ylabel("resident memory (MiB)")
    objects = library_axes.twinx()
    (live,) = objects.plot(
        cycles,
        [row["buffer_count"] + row["texture_count"] for row in library["samples"]],
        color="#d08030",
        label="live wgpu buffers + textures",
    )
    objects.set_ylabel("live wgpu buffers + textures")
    objects.set_ylim(bottom=0)
    trend = library["rss_trend"]
    library_axes.set_title(
        f"library: {trend['slope_kib_per_unit'] * 1000 / 1024:+.2f} MiB per 1000 cycles after warm-up", fontsize=9
    )
    library_axes.legend(handles=[rss, live], loc="upper left", fontsize=8)
    save_figure(chart, path, result, "wgputrace soak: memory over a long session")


def main(argv: list[str] | None = None) -> int:
    parser = argument_parser(__doc__)
    parser.add_argument("--minutes", type=float, default=10.0, help="viewer soak length (default 10; 0 skips it)")
    parser.add_argument("--cycles", type=int, default=10_000, help="library render/edit cycles (default 10000)")
    parser.add_argument(
        "--memory-cap-mib",
        type=int,
        default=MEMORY_CAP_MIB,
        help=f"stop a soaked process whose memory passes this (default {MEMORY_CAP_MIB})",
    )
    args = parse(parser, argv, "cycles", "memory_cap_mib")
    cap_kib = args.memory_cap_mib * 1024
    run = Run()
    viewer = None
    if args.minutes > 0:
        with tempfile.TemporaryDirectory(prefix="wgputrace-soak-") as workdir:
            with nullcontext() if has_display() else virtual_display():
                viewer = soak_viewer(args.minutes, Path(workdir), cap_kib)
        trend = viewer["rss_trend"]
        log(f"viewer: {trend['slope_kib_per_unit']:+.1f} KiB/min, {viewer['actions']}, failures {viewer['failures']}")
    library = soak_library(args.cycles, cap_kib)
    trend = library["rss_trend"]
    log(f"library: {trend['slope_kib_per_unit'] * 1000:+.1f} KiB per 1000 cycles, failures {library['failures']}")
    result = {
        "scene": "default (library); soak_scene.py, the default scene edited (viewer)",
        "width": CYCLE_SIZE[0],
        "height": CYCLE_SIZE[1],
        "spp": 1,
        "max_depth": 9,
        "warmup_fraction": WARMUP_FRACTION,
        "flat_growth_mib": FLAT_GROWTH_MIB,
        "memory_cap_mib": args.memory_cap_mib,
        "viewer": viewer,
        "library": library,
    }
    write_result("soak", result, out=args.out, plot=plot, run=run)
    failures = (viewer["failures"] if viewer else []) + library["failures"]
    for failure in failures:
        log(f"soak: {failure}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
