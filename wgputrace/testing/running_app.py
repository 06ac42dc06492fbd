"""The viewer as a person starts it (`python app.py ...`), in its own process, with its console
lines collected so a test can wait for what it reports."""

from __future__ import annotations

import os
import queue
import re
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgputrace import Camera
from wgputrace.testing.checkout import checkout_file, checkout_root

# Starting a process costs a device (~1.3 s), compiling the kernels (seconds on lavapipe, less
# with Mesa's cache) and the first frames; the CI machine may be busy.
START_SECONDS = 120.0
WAIT_SECONDS = 60.0

_SAVED = re.compile(
    r"saved (?P<png>\S+) and (?P<exr>\S+): (?P<spp>[\d.]+) spp at (?P<width>\d+)x(?P<height>\d+), "
    r"camera (?P<position>\S+ \S+ \S+) dir (?P<forward>\S+ \S+ \S+) speed (?P<speed>\S+) \(showing (?P<shown>[^)]*)\)"
    r"(?: upscale (?P<upscale>\d+))?"
)


@dataclass
class Screenshot:
    png: Path
    exr: Path
    spp: float
    size: tuple[int, int]
    position: np.ndarray
    forward: np.ndarray
    speed: float
    shown: str  # what the radiance view showed: "raw", "SVGF filtered", "motion vectors", ...
    upscale: int  # the moving picture's upscale factor; 1 where the picture was not moving

    def camera(self, vfov_degrees: float) -> Camera:
        return Camera(tuple(self.position), tuple(self.forward), (0.0, 1.0, 0.0), vfov_degrees)


class RunningApp:
    def __init__(self, arguments: list[str], cwd: Path) -> None:
        self.process = subprocess.Popen(
            [sys.executable, str(checkout_file("app.py")), *arguments],
            cwd=cwd,
            env={**os.environ, "PYTHONPATH": str(checkout_root())},
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        self.lines: queue.Queue[str] = queue.Queue()
        self.log: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.process.stdout:
            self.lines.put(line.rstrip("\n"))

    def wait_for(self, pattern: str, timeout: float = WAIT_SECONDS) -> re.Match:
        """The next console line matching `pattern` (a regex), skipping others."""
        deadline = time.monotonic() + timeout
        expression = re.compile(pattern)
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0 or self.process.poll() is not None and self.lines.empty():
                raise AssertionError(
                    f"the viewer printed no line matching {pattern!r} (exit code {self.process.poll()}); it printed:\n"
                    + "\n".join(self.log)
                )
            try:
                line = self.lines.get(timeout=min(remaining, 0.2))
            except queue.Empty:
                continue
            self.log.append(line)
            match = expression.search(line)
            if match:
                return match

    def screenshot_line(self) -> Screenshot:
        match = self.wait_for(_SAVED.pattern)
        return Screenshot(
            Path(match["png"]),
            Path(match["exr"]),
            float(match["spp"]),
            (int(match["width"]), int(match["height"])),
            np.array([float(v) for v in match["position"].split()]),
            np.array([float(v) for v in match["forward"].split()]),
            float(match["speed"]),
            match["shown"],
            int(match["upscale"] or 1),
        )

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
