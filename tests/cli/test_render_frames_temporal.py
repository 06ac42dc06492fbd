"""`wgputrace render-frames --temporal`: an animation's frames in order on one renderer, each
pixel keeping its samples from frame to frame; a per-frame time budget (--frame-ms) or sample
count (--spp), the variance-guided filter's picture (--filtered), temporal upsampling (--upscale);
one-line errors for what it cannot do (bdpt, a cluster, a factor the image is too small for) and
for its options without it."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Camera, Renderer, default_scene
from wgputrace.cli import main
from wgputrace.temporal_frames import follow_frame
from wgputrace.testing.image_statistics import displayed_psnr

pytestmark = pytest.mark.gpu

WIDTH, HEIGHT = 48, 36
SEED = 5
FRAMES = 4
REFERENCE_SPP = 256
# scene(frame) of the default scene, the camera still: every frame adds to one history
RESTING = """import wgputrace as wt


def scene(frame):
    return wt.default_scene()
"""
# the camera sliding sideways: the history moves with the picture
SLIDING = """import wgputrace as wt


def scene(frame):
    scene = wt.default_scene()
    scene.camera = wt.Camera(position=(0.01 * frame, 0.31, -1.2), forward=(0, 0, 1), vfov_degrees=60)
    return scene
"""


def _frames(tmp_path, source: str, *options: str) -> list[np.ndarray]:
    path = tmp_path / "animation.py"
    path.write_text(source)
    output = tmp_path / "out" / "{frame}.npy"
    command = ["render-frames", str(path), "--frames", f"0:{FRAMES}", "--temporal", "--size", f"{WIDTH}x{HEIGHT}"]
    assert main([*command, "--seed", str(SEED), "-o", str(output), *options]) == 0
    return [np.load(tmp_path / "out" / f"{frame}.npy") for frame in range(FRAMES)]


def test_resting_frames_keep_their_samples_the_last_is_the_plain_mean(tmp_path, capsys):
    frames = _frames(tmp_path, RESTING, "--spp", "2")
    plain = Renderer(default_scene(), WIDTH, HEIGHT, seed=SEED)
    plain.render(FRAMES * 2)
    # frames of two samples are Kahan sums of frame sums: the plain mean to float32's rounding
    np.testing.assert_allclose(frames[-1], plain.image(), rtol=2e-7, atol=1e-9)
    assert not np.array_equal(frames[0], frames[-1])
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[:3] for line in lines[:FRAMES]] == [["frame", str(n), "2"] for n in range(FRAMES)]
    assert f"wrote            {FRAMES} frames (accumulated, {WIDTH}x{HEIGHT}, temporal)" in lines[-1]


def test_a_moving_camera_with_a_budget_and_the_filter(tmp_path, capsys):
    accumulated = _frames(tmp_path, SLIDING, "--frame-ms", "1e-6")
    samples = [int(line.split()[2]) for line in capsys.readouterr().out.splitlines()[:FRAMES]]
    assert samples == [1] * FRAMES, "a budget below one pass still takes one sample per pixel"
    (tmp_path / "out").rename(tmp_path / "accumulated")
    filtered = _frames(tmp_path, SLIDING, "--filtered")
    for image in (*accumulated, *filtered):
        assert np.isfinite(image).all() and image.mean() > 0
    reference = default_scene()
    reference.camera = Camera(position=(0.01 * (FRAMES - 1), 0.31, -1.2), forward=(0, 0, 1), vfov_degrees=60)
    converged = Renderer(reference, WIDTH, HEIGHT, seed=SEED + 1)
    converged.render(REFERENCE_SPP)
    # what a person sees: the lamp's radiance, clipped, does not decide it
    psnr = [displayed_psnr(frames[-1], converged.image()) for frames in (accumulated, filtered)]
    assert psnr[1] > psnr[0], f"the filtered frame is no closer to the converged picture (PSNR {psnr})"


def test_upsampled_resting_frames_are_the_plain_mean_and_moving_ones_finite(tmp_path, capsys):
    factor = 2
    # every pixel takes one sample per factor x factor frames
    path = tmp_path / "animation.py"
    path.write_text(RESTING)
    output = str(tmp_path / "rest" / "{frame}.npy")
    frames = 2 * factor * factor
    command = ["render-frames", str(path), "--frames", f"0:{frames}", "--temporal", "--size", f"{WIDTH}x{HEIGHT}"]
    assert main([*command, "--seed", str(SEED), "--upscale", str(factor), "-o", output]) == 0
    last = np.load(tmp_path / "rest" / f"{frames - 1}.npy")
    plain = Renderer(default_scene(), WIDTH, HEIGHT, seed=SEED)
    plain.render(2)
    np.testing.assert_array_equal(last, plain.image())
    assert f"wrote            {frames} frames (accumulated, {WIDTH}x{HEIGHT}, temporal, upsampled 2x)" in (
        capsys.readouterr().out
    )
    for image in _frames(tmp_path, SLIDING, "--upscale", "4", "--filtered"):
        assert np.isfinite(image).all() and image.mean() > 0


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--temporal", "--integrator", "bdpt"], "--temporal: the bdpt integrator writes no G-buffer"),
        (["--temporal", "--ray", "auto"], "--ray: not with --temporal"),
        (["--temporal", "--workers", "2"], "--workers: not with --temporal"),
        (["--frame-ms", "16"], "--frame-ms: only with --temporal"),
        (["--filtered"], "--filtered: only with --temporal"),
        (["--upscale", "2"], "--upscale: only with --temporal"),
        (["--temporal", "--upscale", "8", "--size", "16x4"], "--upscale: upscale 8 needs an image of at least 8x8"),
    ],
)
def test_what_temporal_frames_cannot_do_is_one_line(tmp_path, capsys, options, message):
    path = tmp_path / "animation.py"
    path.write_text(RESTING)
    assert main(["render-frames", str(path), "--frames", "0:2", "-o", str(tmp_path / "{frame}.png"), *options]) == 2
    error = capsys.readouterr().err
    assert message in error and error.count("\n") == 1
    assert not list(tmp_path.glob("*.png"))


def test_following_a_frame_keeps_what_did_not_change():
    scene, following = default_scene(), default_scene()
    shapes = list(scene.shapes)
    versions = [(shape.geometry_version, shape.transform_version, shape.material_version) for shape in shapes]
    following.shapes[0].transform = np.diag([1.0, 1.0, 1.0, 1.0]) + np.eye(4, k=3) * 0.1
    following.camera = Camera(position=(0.1, 0.3, -1.0), forward=(0, 0, 1))
    follow_frame(scene, following)
    assert all(a is b for a, b in zip(scene.shapes, shapes, strict=True)), "shapes of the same geometry are kept"
    np.testing.assert_array_equal(scene.shapes[0].transform, following.shapes[0].transform)
    assert shapes[0].transform_version == versions[0][1] + 1
    assert [(s.geometry_version, s.transform_version, s.material_version) for s in shapes[1:]] == versions[1:]
    assert scene.camera is following.camera
