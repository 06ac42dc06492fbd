"""The viewer on rendercanvas's offscreen canvas (no window needed), for tests of what it draws: a
viewer of a scene, its frames, a scene file rewritten so that the viewer's poll sees it, and the
overlay's error text found in a frame."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from wgputrace.app.options import ViewerOptions
from wgputrace.app.viewer import Viewer

SIZE = (96, 72)
# A lamp over a white floor: small enough for any device, and nothing red in its picture but the
# overlay's error text.
LAMP_OVER_FLOOR = """import wgputrace as wt


def scene():
    lamp = wt.Emitter("lamp")
    white = wt.Diffuse("white")
    return wt.Scene(
        [
            wt.make_plane((0, 1, 2), (-1.5707963, 0, 0), (1, 1), lamp, "lamp"),
            wt.make_plane((0, 0, 2), (0, 0, 0), (4, 4), white, "floor"),
        ],
        wt.Camera.looking_at((0, 1, 0), (0, 0.5, 2)),
    )
"""


def offscreen_viewer(scene: str, screenshot_dir: Path, **options) -> Viewer:
    """A viewer of `scene` (a built-in name or a file) drawing SIZE pixels offscreen; `options`
    as ViewerOptions."""
    from wgputrace.app.window import create_canvas

    canvas = create_canvas(SIZE, "test", offscreen=True)
    return Viewer(canvas, ViewerOptions(scene=scene, size=SIZE, screenshot_dir=screenshot_dir, **options))


def frames(viewer: Viewer, count: int) -> np.ndarray:
    """Draw `count` frames; the last one's pixels."""
    for _ in range(count):
        frame = np.asarray(viewer.canvas.draw())
    return frame


def rewrite(path: Path, text: str) -> None:
    path.write_text(text)
    later = time.time() + 1
    os.utime(path, (later, later))  # a new modification time even within the file system's resolution


# The overlay's error text is drawn in (255, 90, 90): red well above green and blue.
def red_text(frame: np.ndarray) -> np.ndarray:
    pixels = frame[..., :3].astype(int)
    return (pixels[..., 0] > 200) & (pixels[..., 1] < 150) & (pixels[..., 2] < 150)
