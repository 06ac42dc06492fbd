"""`wgputrace render-frames` on the `cluster` fixture, as a user runs it inside the
cluster's namespace: a job stopped by Ctrl-C (SIGINT) keeps the frames it finished, whole, and the
same command then renders the others without writing those again; each frame is the image
wgputrace.render makes of scene(frame)."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.loaders.python_scene import read_python_scene

pytestmark = [pytest.mark.gpu, pytest.mark.slow]

ANIMATION = """
import wgputrace as wt

def scene(frame):
    scene = wt.default_scene()
    scene.camera = wt.Camera.looking_at((0.05 * frame, 1, -3), (0, 0.3, 0), vfov_degrees=45)
    return scene
"""
FRAMES = 8
SIZE = 32
SPP = 8
PATTERN = "{frame:02d}.npy"
WORKERS = 2
# bounds on a job's start (connection, workers), a stop and a whole run
FIRST_FRAME_SECONDS = 120.0
STOP_SECONDS = 30.0
RUN_SECONDS = 120.0


def _command(animation: str, folder: str) -> list[str]:
    return [
        sys.executable,
        "-m",
        "wgputrace",
        "render-frames",
        animation,
        "--frames",
        f"0:{FRAMES}",
        "--spp",
        str(SPP),
        "--size",
        f"{SIZE}x{SIZE}",
        "-o",
        str(Path(folder) / PATTERN),
        "--workers",
        str(WORKERS),
    ]


def _files(folder: str) -> dict[str, tuple[int, int]]:
    """Every file in `folder` (hidden temporaries too): its inode and modification time."""
    return {path.name: (path.stat().st_ino, path.stat().st_mtime_ns) for path in Path(folder).iterdir()}


def _in_namespace_interrupt_and_resume(address: str, animation: str, folder: str) -> dict:
    """Start the job, send SIGINT once its first frame is written, then run it again to the end."""
    command = [*_command(animation, folder), "--ray", address]
    job = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + FIRST_FRAME_SECONDS
    while not any(Path(folder).glob("*.npy")) and job.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    job.send_signal(signal.SIGINT)
    try:
        _, stopped_stderr = job.communicate(timeout=STOP_SECONDS)
    finally:
        job.kill()
    after_stop = _files(folder)
    resumed = subprocess.run(command, capture_output=True, text=True, timeout=RUN_SECONDS)
    return {
        "stopped": (job.returncode, stopped_stderr.strip().splitlines()[-1]),
        "after_stop": after_stop,
        "resumed": (resumed.returncode, resumed.stdout, resumed.stderr),
        "after_resume": _files(folder),
    }


def test_an_interrupted_job_keeps_its_frames_and_resumes(cluster, tmp_path):
    animation = tmp_path / "animation.py"
    animation.write_text(ANIMATION)
    folder = tmp_path / "frames"
    folder.mkdir()
    run = cluster.call(_in_namespace_interrupt_and_resume, cluster.address, str(animation), str(folder), timeout=300)
    status, message = run["stopped"]
    assert status == 128 + signal.SIGINT, message
    assert "SIGINT: stopped; the frames written are kept" in message
    kept = run["after_stop"]
    assert 1 <= len(kept) < FRAMES and all(name.endswith(".npy") and not name.startswith(".") for name in kept), kept
    status, output, errors = run["resumed"]
    assert status == 0, errors
    assert (
        f"skipped          {len(kept)} frames" in output and f"wrote            {FRAMES - len(kept)} frames" in output
    )
    expected = {PATTERN.format(frame=frame) for frame in range(FRAMES)}
    assert set(run["after_resume"]) == expected  # and no temporary left
    assert {name: run["after_resume"][name] for name in kept} == kept  # not written again
    for frame in (0, FRAMES - 1):
        reference = wt.render(read_python_scene(animation, frame), spp=SPP, width=SIZE, height=SIZE, seed=1)
        assert np.array_equal(np.load(folder / PATTERN.format(frame=frame)), reference), f"frame {frame}"
