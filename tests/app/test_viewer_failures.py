"""The viewer survives what fails (offscreen, no window needed): a reloaded scene the device cannot
hold is reported in the picture and on the console while the scene it had stays; a lost device is
replaced and the picture comes back; where no new device can be started, the viewer says why in
one line and closes with exit status 1."""

from __future__ import annotations

import pytest

from wgputrace.gpu import device as gpu_device
from wgputrace.testing.offscreen_viewer import LAMP_OVER_FLOOR, frames, offscreen_viewer, red_text, rewrite

pytestmark = pytest.mark.gpu

# max-texture-dimension-2d as this test pretends the device offers it: LAMP_OVER_FLOOR's triangle
# texture (4 triangles, 6 rows) fits, the default scene's (676 triangles, 64 rows) does not.
SMALL_TEXTURE_LIMIT = 16
DEFAULT = "import wgputrace as wt\n\n\ndef scene():\n    return wt.default_scene()\n"


@pytest.fixture
def own_device(monkeypatch):
    """gpu() hands out a device of this test's own (and a new one each time it is lost): losing
    it leaves the session's device to the other tests."""
    monkeypatch.setattr(gpu_device, "_context", gpu_device.new_context())


def test_a_reloaded_scene_beyond_the_device_limits_is_reported_and_the_scene_shown_stays(
    gpu_context, monkeypatch, tmp_path, capsys
):
    monkeypatch.setitem(gpu_context.device.limits, "max-texture-dimension-2d", SMALL_TEXTURE_LIMIT)
    path = tmp_path / "scene.py"
    path.write_text(LAMP_OVER_FLOOR)
    viewer = offscreen_viewer(str(path), tmp_path)
    frames(viewer, 2)
    shown, view = viewer.scene, viewer.view
    assert view is not None and viewer.errors == []

    rewrite(path, DEFAULT)
    viewer.shown.next_poll = 0.0  # do not wait for the next poll
    frame = frames(viewer, 2)
    assert viewer.scene is shown and viewer.view is view, "the scene shown was replaced"
    assert "max-texture-dimension-2d" in viewer.errors[0] and "still showing the previous scene" in viewer.errors[1]
    refusal = [line for line in capsys.readouterr().err.splitlines() if "scene not shown" in line]
    assert len(refusal) == 1 and "max-texture-dimension-2d" in refusal[0], "reported once, on one line"
    assert red_text(frame).sum() > 20, "the error is not in the picture"
    assert frame[..., :3].max() > 0

    rewrite(path, LAMP_OVER_FLOOR)
    viewer.shown.next_poll = 0.0
    frame = frames(viewer, 3)
    assert viewer.scene is not shown and viewer.errors == [] and not red_text(frame).any()


def test_a_lost_device_is_replaced_and_without_a_new_one_the_viewer_closes_saying_why(
    own_device, monkeypatch, tmp_path, capsys
):
    viewer = offscreen_viewer("cornell", tmp_path)
    frames(viewer, 2)
    lost = viewer.device.context
    lost.device.destroy()
    frame = frames(viewer, 4)
    assert viewer.device.context is not lost and viewer.device.context.lost_reason is None
    assert viewer.exit_status == 0 and not viewer.canvas.get_closed()
    assert frame[..., :3].max() > 0, "no picture after the device was replaced"
    assert "the GPU device was lost" in capsys.readouterr().err

    def no_adapter():
        raise RuntimeError("wgpu found no adapter")

    monkeypatch.setattr(gpu_device, "new_context", no_adapter)
    viewer.device.context.device.destroy()
    viewer.canvas.draw()
    assert viewer.exit_status == 1 and viewer.canvas.get_closed()
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert "the GPU device was lost" in last and "no new one could be started: wgpu found no adapter" in last
