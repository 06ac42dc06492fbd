"""The command line, run as a user would: a separate process, files on disk."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wgputrace import Renderer, default_scene, load_image
from wgputrace.app import options_from
from wgputrace.cli import argument_parser
from wgputrace.cli_arguments import UsageError

pytestmark = pytest.mark.gpu  # every command here opens the adapter


@pytest.mark.parametrize("suffix", [".png", ".exr", ".npy"])
def test_render_writes_each_format(tmp_path, suffix, run_cli):
    out = tmp_path / f"cornell{suffix}"
    result = run_cli("render", "--spp", "2", "--size", "24x16", "--seed", "5", "-o", str(out))
    assert result.returncode == 0, result.stderr
    image = load_image(out)
    assert image.shape == (16, 24, 3)
    assert np.all(np.isfinite(image)) and image.max() > 0
    for label in ("adapter", "676 triangles", "SAH cost", "built in", "M samples/s"):
        assert label in result.stdout


def test_exr_and_npy_hold_the_same_linear_image(tmp_path, run_cli):
    for suffix in (".exr", ".npy"):
        assert run_cli("render", "--spp", "1", "--size", "8x8", "-o", str(tmp_path / f"a{suffix}")).returncode == 0
    np.testing.assert_array_equal(load_image(tmp_path / "a.exr"), load_image(tmp_path / "a.npy"))


def test_errors_are_clear(tmp_path, run_cli):
    unknown = run_cli("render", "nowhere", "--spp", "1", "-o", str(tmp_path / "x.png"))
    assert unknown.returncode == 2 and "unknown scene 'nowhere'; built-in scenes: " in unknown.stderr
    assert "cornell" in unknown.stderr.split("built-in scenes: ")[1]
    missing = run_cli("render", str(tmp_path / "nowhere.glb"), "--spp", "1", "-o", str(tmp_path / "x.png"))
    assert missing.returncode == 2 and missing.stderr == f"wgputrace: error: {tmp_path / 'nowhere.glb'}: no such file\n"
    bad_format = run_cli("render", "--spp", "1", "--size", "8x8", "-o", str(tmp_path / "x.jpg"))
    assert bad_format.returncode == 2 and "unknown image format '.jpg'" in bad_format.stderr
    bad_size = run_cli("render", "--size", "big")
    assert bad_size.returncode == 2 and "size must look like 512x512" in bad_size.stderr


def test_info_prints_adapter_and_limits(run_cli):
    result = run_cli("info")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["adapter"] and info["backend"]
    assert "max-storage-buffer-binding-size" in info["limits"]


def test_time_limit_and_info_of_the_file(tmp_path, run_cli):
    out = tmp_path / "limited.npy"
    result = run_cli("render", "--size", "8x8", "--time-limit", "0.2", "--seed", "3", "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert "stopped by time limit" in result.stdout
    info = run_cli("info", str(out))
    assert info.returncode == 0, info.stderr
    fields = dict(line.split(maxsplit=1) for line in info.stdout.splitlines())
    assert int(fields["spp"]) >= 1 and fields["seed"] == "3" and fields["stopped_by"] == "time limit"
    assert f"wrote            {out} ({fields['spp']} spp)" in result.stdout


def test_debug_shows_the_traceback(run_cli):
    quiet = run_cli("render", "nowhere")
    assert quiet.returncode == 2 and len(quiet.stderr.splitlines()) == 1
    loud = run_cli("--debug", "render", "nowhere")
    assert loud.returncode == 1 and "Traceback" in loud.stderr and "SceneLoadError" in loud.stderr


@pytest.mark.parametrize(("integrator", "sampler"), [("mis", "independent"), ("bdpt", "sobol")])
def test_integrator_and_sampler_reach_the_renderer(tmp_path, run_cli, integrator, sampler):
    out = tmp_path / "a.npy"
    args = ("render", "--spp", "2", "--size", "12x8", "--seed", "2", "--integrator", integrator, "--sampler", sampler)
    assert run_cli(*args, "-o", str(out)).returncode == 0
    expected = Renderer(default_scene(), 12, 8, seed=2, integrator=integrator, sampler=sampler)
    expected.render(2)
    np.testing.assert_array_equal(load_image(out), expected.image())
    fields = dict(line.split(maxsplit=1) for line in run_cli("info", str(out)).stdout.splitlines())
    assert (fields["integrator"], fields["sampler"]) == (integrator, sampler)


def test_view_takes_the_integrators_with_a_viewer_kernel():
    args = argument_parser().parse_args(["view", "box.glb", "--integrator", "restir"])
    assert options_from(args).integrator == "restir"
    # bdpt renders whole images only: no band-of-rows kernel for the viewer
    with pytest.raises(UsageError, match="invalid choice: 'bdpt'"):
        argument_parser().parse_args(["view", "box.glb", "--integrator", "bdpt"])
