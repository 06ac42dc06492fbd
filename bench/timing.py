"""Timed renders: a fresh image timed by wall and process CPU clock, the runs of one kind of work
with their medians, and the rays of a timed render counted by replaying its samples."""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass, field

import numpy as np

from wgputrace import Renderer
from wgputrace.render.ray_count import RayCounts, count_rays


def fresh_image(renderer: Renderer, spp: int, *, from_seed: bool = False) -> tuple[np.ndarray, int, float, float]:
    """Forget earlier samples, render `spp`: (image, dropped samples, wall seconds, process CPU seconds).

    The random sequences continue (new, independent samples), or with `from_seed` start again at
    the seed (the same samples as every other render from the seed). Only the render is timed: the
    clear of the accumulation buffer is waited for before the clock starts, and the read-back of
    the image happens after it stops. Process CPU time includes llvmpipe's worker threads and
    hardly changes with other load on a CPU adapter's cores, which wall time does.
    """
    if from_seed:
        renderer.restart()
    else:
        renderer.reset()
    renderer.context.finish()
    wall, cpu = time.perf_counter(), time.process_time()
    renderer.render(spp)  # returns once every dispatch has finished
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return renderer.image(), renderer.dropped_samples, wall, cpu


@dataclass
class Timed:
    """One measured kind of work: `units` (paths or rays) per run, wall and process CPU seconds per run."""

    units: int
    wall: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)

    def add(self, wall: float, cpu: float) -> None:
        self.wall.append(wall)
        self.cpu.append(cpu)

    def entry(self, unit: str = "paths") -> dict:
        """Runs, medians and the rate of the median run, for the result file."""
        median = statistics.median(self.wall)
        return {
            f"{unit}_per_run": self.units,
            "run_seconds": self.wall,
            "run_process_cpu_seconds": self.cpu,
            "median_seconds": median,
            "median_process_cpu_seconds": statistics.median(self.cpu),
            f"{unit}_per_second": self.units / median,
        }


def counted_rays(renderer: Renderer, spp: int, timed_image: np.ndarray) -> RayCounts:
    """Count the rays of a timed render of `spp` from the seed: the same samples again through the
    path tracer with ray counters compiled in, whose image must equal `timed_image` bit for bit
    (the proof that the counts belong to the timed paths)."""
    renderer.restart()
    counts = count_rays(renderer, spp)
    if not np.array_equal(renderer.image(), timed_image):
        raise SystemExit("the counted render's image differs from the timed one's")
    return counts


def ray_rates(counts: RayCounts, seconds: float) -> dict:
    """Camera rays and all rays (camera, extension, shadow) per second of a render that took `seconds`."""
    return {
        "camera_rays_per_second": counts.camera / seconds,
        "rays_per_second": counts.total / seconds,
        "rays_per_path": counts.total / counts.camera,
        "rays": {"camera": counts.camera, "extension": counts.extension, "shadow": counts.shadow, "all": counts.total},
    }
