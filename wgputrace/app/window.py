"""Where the viewer draws: a glfw window through rendercanvas, rendercanvas's offscreen canvas,
or a virtual X display (Xvfb) for running the window without a screen (tests, benchmarks)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

# rendercanvas schedules draws no faster than this; the viewer's own frame budget is the real limit.
MAX_FPS = 240.0
XVFB_SCREEN = "1920x1200x24"
XVFB_START_SECONDS = 10.0


class NoDisplayError(RuntimeError):
    """There is no screen to open a window on."""


def has_display() -> bool:
    """Whether a window can be opened: always on Windows and macOS, with DISPLAY or WAYLAND_DISPLAY on Linux."""
    if sys.platform in ("win32", "darwin"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def create_canvas(size: tuple[int, int], title: str, *, offscreen: bool = False):
    """A rendercanvas canvas drawing continuously. Without a display glfw would abort the whole
    process (a GLFW assertion, not an exception), so that case is checked first."""
    if offscreen:
        from rendercanvas.offscreen import RenderCanvas
    else:
        if not has_display():
            raise NoDisplayError(
                "no display to open a window on (DISPLAY is not set): run under a virtual display, "
                "e.g. `xvfb-run -a wgputrace view`"
            )
        from rendercanvas.glfw import RenderCanvas
    return RenderCanvas(size=size, title=title, update_mode="continuous", max_fps=MAX_FPS)


def run_loop() -> None:
    from rendercanvas.glfw import loop

    loop.run()


@contextmanager
def virtual_display(screen: str = XVFB_SCREEN) -> Iterator[str]:
    """Start Xvfb on a free display number, set DISPLAY to it for the block, stop it after."""
    if shutil.which("Xvfb") is None:
        raise NoDisplayError("Xvfb is not installed (Debian: apt-get install xvfb)")
    read_end, write_end = os.pipe()
    process = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_end), "-screen", "0", screen, "-nolisten", "tcp"],
        pass_fds=(write_end,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_end)
    try:
        with os.fdopen(read_end) as announcement:
            number = announcement.readline().strip()
        if not number:
            raise NoDisplayError(f"Xvfb exited with {process.wait(XVFB_START_SECONDS)} before announcing a display")
        display = f":{number}"
        previous = os.environ.get("DISPLAY")
        os.environ["DISPLAY"] = display
        try:
            yield display
        finally:
            if previous is None:
                os.environ.pop("DISPLAY", None)
            else:
                os.environ["DISPLAY"] = previous
    finally:
        process.terminate()
        process.wait(XVFB_START_SECONDS)
