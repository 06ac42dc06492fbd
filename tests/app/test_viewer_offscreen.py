"""The viewer drawing into rendercanvas's offscreen canvas (no window needed): a scene file that
fails shows its error in the picture and on the console and the viewer keeps running; fixing the
file reloads it. And the notebook backend's code path, where jupyter_rfb is installed."""

from __future__ import annotations

import time

import numpy as np
import pytest

from wgputrace.testing.offscreen_viewer import LAMP_OVER_FLOOR, SIZE, offscreen_viewer, red_text, rewrite

pytestmark = pytest.mark.gpu

BROKEN = "import wgputrace as wt\n\n\ndef scene():\n    return wt.Scene([wt.make_plane((0, 0, 2), (0, 0, 0), (1, 1), None)])\n"


def test_a_failing_scene_file_is_shown_and_the_viewer_keeps_running(gpu_context, tmp_path, capsys):
    path = tmp_path / "scene.py"
    path.write_text(BROKEN)
    viewer = offscreen_viewer(str(path), tmp_path)
    frame = np.asarray(viewer.canvas.draw())
    assert viewer.scene is None and "scene.py:5: " in viewer.errors[0]
    assert "scene.py:5: " in capsys.readouterr().err
    assert red_text(frame).sum() > 20, "the error is not in the picture"

    rewrite(path, LAMP_OVER_FLOOR)
    viewer.shown.next_poll = 0.0  # do not wait for the next poll
    for _ in range(3):
        frame = np.asarray(viewer.canvas.draw())
    assert viewer.scene is not None and viewer.errors == []
    assert frame[..., :3].max() > 0 and not red_text(frame).any()

    rewrite(path, BROKEN)
    viewer.shown.next_poll = 0.0
    viewer.canvas.draw()
    frame = np.asarray(viewer.canvas.draw())
    assert "scene.py:5" in viewer.errors[0] and "still showing the previous scene" in viewer.errors[1]
    assert viewer.scene is not None and red_text(frame).sum() > 20


def test_the_notebook_viewer_draws_and_takes_events_without_a_browser(gpu_context):
    pytest.importorskip("jupyter_rfb", reason="the notebook extra is not installed")
    from wgputrace.app import notebook_viewer

    viewer = notebook_viewer("cornell", size=SIZE)
    from jupyter_rfb import RemoteFrameBuffer

    assert isinstance(viewer.canvas, RemoteFrameBuffer)
    viewer.canvas.get_frame()  # what the widget does when the browser asks for a frame
    assert viewer.frames, "no frame was drawn"
    before = viewer.controller.position.copy()
    viewer.canvas.handle_event({"event_type": "key_down", "key": "w", "modifiers": [], "time_stamp": 0.0})
    time.sleep(0.05)
    viewer.canvas.handle_event({"event_type": "key_up", "key": "w", "modifiers": [], "time_stamp": 0.0})
    viewer.canvas.get_frame()
    assert viewer.controller.position[2] > before[2]
