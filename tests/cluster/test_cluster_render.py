"""Rendering on the two-node `cluster` fixture: the same bits for one worker (in tiles), for
two (through `wgputrace render --ray`), and for three with one of them killed mid-run; the picture wgputrace.render converges to; and clear
errors, bounded in time, for a bad address, a scene that fails on the workers and an image larger
than the workers' device allows.

The functions named _in_namespace_* run inside the cluster's namespace (cluster.call)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import numpy as np
import pytest

import wgputrace as wt
from wgputrace.cluster import ClusterUnreachable, WorkerFailed, render_batches, render_frames
from wgputrace.cluster.batches import split_samples
from wgputrace.cluster.merge import TiledSum
from wgputrace.cluster.worker import RenderSettings, RenderWorker
from wgputrace.testing.image_statistics import BLOCKS, CHANNELS, block_z_scores
from wgputrace.testing.stats import sidak, z_limit

pytestmark = [pytest.mark.gpu, pytest.mark.slow]

SIZE = 32
SPP = 12
BATCHES = 6
SEED = 3
TILE = 20  # 2 x 2 tiles of 16 x 16
# the z-test against wgputrace.render: a family of BLOCKS^2 x CHANNELS tests at this level
SIGNIFICANCE = 1e-3
# wgputrace.render's seed there: none of the cluster's batch seeds
INDEPENDENT_SEED = 1000
# larger than lavapipe's 2 GiB max-buffer-size allows (its random states alone need 6.4 GB)
TOO_LARGE = 20_000


def _in_namespace_render(address: str, workers: int, kill_a_worker: bool = False, tile: int | None = None) -> dict:
    """Render the Cornell box on `workers` workers (in tiles of `tile`); with `kill_a_worker`, the
    worker that finishes the first batch is killed (SIGKILL, by its pid) while its next batch is
    queued on it."""
    killed = []

    def kill_first(progress):
        if kill_a_worker and not killed:
            os.kill(progress.last_worker.pid, signal.SIGKILL)
            killed.append(progress.last_worker.pid)

    result = render_batches(
        wt.default_scene(),
        SPP,
        SIZE,
        SIZE,
        seed=SEED,
        address=address,
        batches=BATCHES,
        workers=workers,
        tile=tile,
        progress=kill_first,
    )
    return {
        "image": result.image,
        "workers": [worker.pid for worker in result.workers],
        "lost": result.lost_workers,
        "resubmitted": result.resubmitted_batches,
        "killed": killed,
    }


def _merged_here(tile: int | None) -> np.ndarray:
    """The batches (of every tile) rendered one after the other in this process, merged in order."""
    settings = RenderSettings(SIZE, SIZE, SEED, tile_side=tile)
    worker = RenderWorker()
    worker.prepare(wt.default_scene(), settings)
    merged = TiledSum(SIZE, SIZE, settings.tiles())
    for batch in split_samples(SPP, SEED, BATCHES):
        for piece in settings.tiles():
            merged.add(piece, worker.render_batch(batch, piece).image)
    return merged.image()


@pytest.fixture(scope="module")
def expected() -> np.ndarray:
    return _merged_here(None)


def _in_namespace_command_line(address: str, output: str) -> tuple[int, str, str]:
    """`wgputrace render --ray` of the same render, in a process of its own."""
    command = ["render", "--ray", address, "--batches", str(BATCHES), "--spp", str(SPP), "--workers", "2"]
    command += ["--size", f"{SIZE}x{SIZE}", "--seed", str(SEED), "-o", output]
    done = subprocess.run([sys.executable, "-m", "wgputrace", *command], capture_output=True, text=True, timeout=120)
    return done.returncode, done.stdout, done.stderr


@pytest.fixture(scope="module")
def two_workers(cluster, tmp_path_factory) -> dict:
    """The render on two workers, by `wgputrace render --ray` in a process of its own."""
    output = tmp_path_factory.mktemp("cluster") / "cluster.npy"
    status, printed, errors = cluster.call(_in_namespace_command_line, cluster.address, str(output), timeout=150)
    assert status == 0, errors
    return {"image": np.load(output), "printed": printed}


def test_one_worker_gives_the_batches_merged_in_order_tiles_too(cluster):
    run = cluster.call(_in_namespace_render, cluster.address, 1, tile=TILE)
    assert np.array_equal(run["image"], _merged_here(TILE))


def test_two_workers_give_the_same_bits_through_the_command_line(two_workers, expected):
    assert f"{SPP} spp at {SIZE}x{SIZE} in {BATCHES} batches" in two_workers["printed"]
    assert np.array_equal(two_workers["image"], expected)


def test_three_workers_one_killed_mid_run_give_the_same_bits(cluster, expected):
    run = cluster.call(_in_namespace_render, cluster.address, 3, kill_a_worker=True)
    assert run["lost"] == 1 and run["resubmitted"] >= 1, run
    assert len(set(run["workers"])) >= 2 and run["killed"][0] in run["workers"]  # killed after its first batch
    assert np.array_equal(run["image"], expected)


def test_the_cluster_converges_to_wgputrace_render(two_workers):
    reference = wt.render(wt.default_scene(), spp=SPP, width=SIZE, height=SIZE, seed=INDEPENDENT_SEED)
    scores = block_z_scores(two_workers["image"], reference)
    limit = z_limit(sidak(SIGNIFICANCE, BLOCKS * BLOCKS * CHANNELS))
    assert np.abs(scores).max() < limit, f"block z-scores {np.round(scores, 1).tolist()} beyond {limit:.2f}"


def _in_namespace_error(call: str, address: str, path: str = "") -> tuple[str, str]:
    """The error's type and message."""
    try:
        if call == "frames":
            render_frames(path, range(0, 2), path + ".{frame}.npy", 1, 8, 8, address=address, workers=1)
        else:
            render_batches(
                wt.default_scene(), 1, *(2 * [TOO_LARGE if call == "too large" else 8]), address=address, workers=1
            )
    except Exception as error:
        return type(error).__name__, str(error)
    return "", "no error"


@pytest.mark.parametrize("address", ["127.0.0.1:1", "192.0.2.1:6379"])
def test_an_unreachable_address_is_named(cluster, address):
    kind, message = cluster.call(_in_namespace_error, "render", address, timeout=30)
    assert kind == ClusterUnreachable.__name__
    assert message.startswith(f"Ray cluster at {address}: cannot connect")


def test_a_scene_failing_on_the_workers_surfaces_its_message(cluster, tmp_path):
    animation = tmp_path / "animation.py"
    animation.write_text("def scene(frame):\n    raise RuntimeError(f'no frame {frame} here')\n")
    kind, message = cluster.call(_in_namespace_error, "frames", cluster.address, str(animation), timeout=60)
    assert kind == WorkerFailed.__name__
    assert message.startswith("worker ") and f"): SceneLoadError: {animation}:2: RuntimeError: no frame " in message


def test_an_image_beyond_the_device_is_refused_by_the_worker(cluster):
    kind, message = cluster.call(_in_namespace_error, "too large", cluster.address, timeout=60)
    assert kind == WorkerFailed.__name__
    assert f"DeviceLimitError: a {TOO_LARGE:,}x{TOO_LARGE:,} image" in message
