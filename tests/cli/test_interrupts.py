"""SIGINT and SIGTERM sent to `wgputrace render` at pseudo-random moments (a fixed seed draws them):
the file written holds exactly the samples its metadata claims (bit for bit a fresh render of that
many), the exit status and the one-line message say what happened, and no temporary file is left.
A second signal aborts, leaving no file at all."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import wgputrace
import wgputrace as wt
from wgputrace.image_io import sidecar_path, srgb8, tonemap
from wgputrace.provenance import NAMESPACE, read_metadata

pytestmark = [pytest.mark.gpu, pytest.mark.slow]  # each case starts a process and renders twice

SIZE, SEED = 32, 11
ENDLESS_SPP = 1_000_000
MOMENT_SEED = 20261201
LATEST_SIGNAL_SECONDS = 0.6
PACKAGE_PARENT = Path(wgputrace.__file__).resolve().parents[1]


class RenderProcess:
    """`python -m wgputrace render` writing `output`, its stderr collected as it comes (tqdm writes
    it with carriage returns, so not line by line)."""

    def __init__(self, output: Path) -> None:
        self.output = output
        path = os.pathsep.join(filter(None, [str(PACKAGE_PARENT), os.environ.get("PYTHONPATH")]))
        command = [sys.executable, "-m", "wgputrace", "render", "--size", f"{SIZE}x{SIZE}", "--seed", str(SEED)]
        self.process = subprocess.Popen(
            [*command, "--spp", str(ENDLESS_SPP), "-o", str(output)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            env={**os.environ, "PYTHONPATH": path},
        )
        self.stderr = b""
        self._reader = threading.Thread(target=self._read_stderr, daemon=True)
        self._reader.start()

    def _read_stderr(self) -> None:
        while chunk := os.read(self.process.stderr.fileno(), 4096):
            self.stderr += chunk

    def wait_until_rendering(self, timeout: float = 120.0) -> None:
        deadline = time.monotonic() + timeout
        while b"rendering" not in self.stderr:
            assert self.process.poll() is None, f"ended before rendering: {self.stderr.decode()}"
            assert time.monotonic() < deadline, "rendering did not start"
            time.sleep(0.01)

    def finish(self) -> tuple[int, str, str]:
        """Exit status, stdout, and the last line of stderr (the progress bar comes before it)."""
        stdout = self.process.stdout.read()  # not communicate(): the reader thread owns stderr
        self.process.wait(timeout=120)
        self._reader.join()
        return self.process.returncode, stdout.decode(), self.stderr.decode().splitlines()[-1]


def signal_moment(case: str) -> float:
    """Seconds after rendering started at which `case` sends its signal: drawn, but the same on every run."""
    return random.Random(f"{MOMENT_SEED}:{case}").uniform(0.0, LATEST_SIGNAL_SECONDS)


def fresh_render(spp: int) -> np.ndarray:
    renderer = wt.Renderer(wt.load_scene("cornell"), SIZE, SIZE, seed=SEED)
    renderer.render(spp)
    return renderer.image()


def assert_holds_what_it_claims(output: Path, signal_name: str) -> None:
    metadata = read_metadata(output)
    spp = int(metadata[NAMESPACE + "spp"])
    assert metadata[NAMESPACE + "stopped_by"] == signal_name
    expected = fresh_render(spp)
    if output.suffix == ".png":
        np.testing.assert_array_equal(np.asarray(Image.open(output).convert("RGB")), srgb8(tonemap(expected)))
    else:
        np.testing.assert_array_equal(wt.load_image(output), expected)


@pytest.mark.parametrize(
    ("suffix", "stop"),
    [(".png", signal.SIGINT), (".exr", signal.SIGTERM), (".npy", signal.SIGINT), (".png", signal.SIGTERM)],
)
def test_a_signal_keeps_the_samples_done(tmp_path, suffix, stop):
    output = tmp_path / f"out{suffix}"
    render = RenderProcess(output)
    render.wait_until_rendering()
    time.sleep(signal_moment(f"{suffix} {stop.name}"))
    render.process.send_signal(stop)
    status, stdout, message = render.finish()
    name = signal.Signals(stop).name
    assert status == 128 + stop
    written = {output.name, sidecar_path(output).name} if suffix == ".npy" else {output.name}
    if output.exists():
        spp = int(read_metadata(output)[NAMESPACE + "spp"])
        assert message == f"wgputrace: {name}: stopped, {output} holds {spp} spp"
        assert f"wrote            {output} ({spp} spp)" in stdout
        assert_holds_what_it_claims(output, name)
        assert {path.name for path in tmp_path.iterdir()} == written
    else:  # the signal came before the first sample finished
        assert message == f"wgputrace: {name}: stopped, no sample finished, {output} not written"
        assert not any(tmp_path.iterdir())


def test_a_second_signal_aborts_and_writes_nothing(tmp_path):
    output = tmp_path / "out.exr"
    render = RenderProcess(output)
    render.wait_until_rendering()
    time.sleep(signal_moment("second signal"))
    # back to back: Python runs the handlers in signal number order, SIGINT's first
    render.process.send_signal(signal.SIGINT)
    render.process.send_signal(signal.SIGTERM)
    status, _, message = render.finish()
    assert status == 143
    assert message == f"wgputrace: second signal (SIGTERM): aborted, {output} not written"
    assert not any(tmp_path.iterdir())
