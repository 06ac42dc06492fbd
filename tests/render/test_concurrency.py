"""Renderers sharing a device, and processes sharing an adapter, each make the picture they make
alone, bit for bit. The two jobs differ in scene, size and seed, so an image that picked up the
other job's buffers, frame or samples would show it."""

from __future__ import annotations

import subprocess
import sys
import threading

import numpy as np
import pytest

import wgputrace as wt

pytestmark = pytest.mark.gpu

# (scene, width, height, seed): different in everything, so a mix-up cannot go unseen.
JOBS = (("cornell", 24, 16, 1), ("glossy_spheres", 16, 24, 7))
# Several renders per thread, so the two threads' submits interleave rather than run one after
# the other.
RENDERS = 8
PROCESS_SECONDS = 300


def renderer(job) -> wt.Renderer:
    scene, width, height, seed = job
    return wt.Renderer(wt.load_scene(scene), width, height, seed=seed)


def alone(job) -> np.ndarray:
    single = renderer(job)
    single.render(RENDERS)
    return single.image()


def test_two_renderers_on_one_device_in_two_threads_render_what_they_render_alone(gpu_context):
    expected = [alone(job) for job in JOBS]
    start = threading.Barrier(len(JOBS))
    results: dict[int, wt.Renderer] = {}
    errors: list[BaseException] = []

    def work(number: int) -> None:
        try:
            start.wait()
            # made in the thread too: buffers, bind groups and uploads on the shared device at once
            each = results[number] = renderer(JOBS[number])
            for _ in range(RENDERS):
                each.render(1)
        except BaseException as error:  # reported by the main thread, which fails the test
            errors.append(error)

    threads = [threading.Thread(target=work, args=(number,)) for number in range(len(JOBS))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors, f"a rendering thread failed: {errors[0]!r}"
    for number, image in enumerate(expected):
        assert results[number].context.device is gpu_context.device
        assert results[number].samples_per_pixel == RENDERS
        np.testing.assert_array_equal(results[number].image(), image)


@pytest.mark.slow
def test_two_processes_on_one_adapter_render_what_they_render_alone(tmp_path):
    outputs = [tmp_path / f"job{number}.npy" for number in range(len(JOBS))]
    processes = [
        subprocess.Popen(
            [sys.executable, "-m", "wgputrace", "render", scene, "--size", f"{width}x{height}", "--seed", str(seed)]
            + ["--spp", str(RENDERS), "-o", str(output)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
        )
        for (scene, width, height, seed), output in zip(JOBS, outputs, strict=True)
    ]
    for process in processes:
        _, errors = process.communicate(timeout=PROCESS_SECONDS)
        assert process.returncode == 0, errors
    for job, output in zip(JOBS, outputs, strict=True):
        np.testing.assert_array_equal(wt.load_image(output), alone(job))
