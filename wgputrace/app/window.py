"""Where the viewer draws: a glfw window through rendercanvas, or rendercanvas's offscreen canvas.
Without a screen, the window opens on a virtual X display (wgputrace.testing.display, xvfb-run)."""

from __future__ import annotations

import os
import sys

# rendercanvas schedules draws no faster than this; the viewer's own frame budget is the real limit.
MAX_FPS = 240.0


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
