"""A virtual X display (Xvfb): the viewer's real glfw window opens on it where there is no screen
(tests, benchmarks on a headless machine)."""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager

from wgputrace.app.window import NoDisplayError

XVFB_SCREEN = "1920x1200x24"
XVFB_START_SECONDS = 10.0


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
