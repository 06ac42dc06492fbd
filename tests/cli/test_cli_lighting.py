"""Lighting on the command line: a scene that brings no light is lit by the default environment
and the CLI says so; --env none renders black; --env VALUE (a number or r,g,b) and --env FILE with
--env-intensity and --env-rotation set the environment `apply_lighting` gives the scene; bad
values are one line and status 2."""

from __future__ import annotations

import argparse
import contextlib
import io
from pathlib import Path

import numpy as np
import pytest

from wgputrace import load_image, load_scene, save_image
from wgputrace.cli import argument_parser, main
from wgputrace.cli_arguments import apply_lighting
from wgputrace.testing.gltf_files import (
    BOX,
    BOX_INDICES,
    LIGHTS,
    gltf_document,
    light_node,
    textured_asset_glb,
    with_lights,
    write_glb,
)

DEFAULT_NOTE = "lighting         the scene brings no light: lit by the default environment"
# Small and few samples: what is checked is exact under BSDF sampling (below) or a mean far from 0.
RENDER = ["--size", "16x16", "--spp", "2"]
GREY = 0.8  # the loader's albedo for a primitive without a material


@pytest.fixture
def lightless_box(tmp_path) -> Path:
    """A grey box in a glTF file with no light, framed by the loader (the image's corners see the
    background: the bounding sphere just fills the height)."""
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    return write_glb(tmp_path / "box.glb", document, blob)


def run(argv: list[str], cwd: Path) -> tuple[int, str, str]:
    """main(argv) in this process, in the working directory `cwd`: (status, stdout, stderr)."""
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.chdir(cwd), contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        status = main(argv)
    return status, stdout.getvalue(), stderr.getvalue()


def parsed(*options: str) -> argparse.Namespace:
    return argument_parser().parse_args(["render", *options])


def test_default_environment_only_where_the_scene_brings_no_light(lightless_box, tmp_path):
    scene = load_scene(lightless_box)
    note = apply_lighting(scene, parsed())
    assert note.startswith("the scene brings no light: lit by the default environment, a constant radiance of 1")
    assert scene.environment.radiance == (1.0, 1.0, 1.0)
    cornell = load_scene("cornell")  # lit by its lamp
    assert apply_lighting(cornell, parsed()) is None and cornell.environment is None
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    with_lights(document, LIGHTS[:1], [light_node(0, translation=[0, 3, 0])])
    lamp = load_scene(write_glb(tmp_path / "lamp.glb", document, blob))  # lit by its glTF light
    assert apply_lighting(lamp, parsed()) is None and lamp.environment is None
    glowing = load_scene(textured_asset_glb(tmp_path / "asset.glb"))  # lit by its emissive texture
    assert apply_lighting(glowing, parsed()) is None and glowing.environment is None


def test_env_options_set_the_environment(lightless_box, tmp_path):
    for options, radiance in ((["--env", "0.5"], (0.5,) * 3), (["--env", "1,0,0"], (1.0, 0.0, 0.0))):
        scene = load_scene("cornell")
        assert apply_lighting(scene, parsed(*options)) is None
        assert scene.environment.radiance == radiance
    scene = load_scene(lightless_box)
    assert apply_lighting(scene, parsed("--env", "none")) is None and scene.environment is None
    sky = save_image(tmp_path / "sky.exr", np.full((2, 4, 3), 0.25, np.float32))
    scene = load_scene(lightless_box)
    apply_lighting(scene, parsed("--env", str(sky), "--env-intensity", "2", "--env-rotation", "-90"))
    assert (scene.environment.intensity, scene.environment.rotation_degrees) == (2.0, -90.0)
    np.testing.assert_allclose(scene.environment.lookup(np.array([[0.0, 1.0, 0.0]])), [[0.5, 0.5, 0.5]])
    scene = load_scene(lightless_box)
    apply_lighting(scene, parsed("--env-intensity", "3"))  # the default environment, three times as bright
    np.testing.assert_allclose(scene.environment.lookup(np.array([[0.0, 1.0, 0.0]])), [[3.0, 3.0, 3.0]])


@pytest.mark.parametrize(
    "options, message",
    [
        (["--env", "-1"], "argument --env: a constant radiance is one number or r,g,b, each finite and >= 0, got '-1'"),
        (["--env", "nan"], "argument --env: a constant radiance is one number or r,g,b"),
        (["--env", "1,2"], "argument --env: a constant radiance is one number or r,g,b"),
        (["--env", "1,0,inf"], "argument --env: a constant radiance is one number or r,g,b"),
        (["--env", "missing.hdr"], "argument --env: missing.hdr: no such file; give an environment map"),
        (["--env-intensity", "-2"], "argument --env-intensity: must be a finite number above 0, got '-2'"),
        (["--env-rotation", "nan"], "argument --env-rotation: must be a finite number, got 'nan'"),
        (
            ["--env", "none", "--env-intensity", "2"],
            "--env-intensity 2: there is no environment to apply it to (--env none",
        ),
        (["--env-rotation", "30"], "--env-rotation 30: there is no environment to apply it to (the scene has none"),
    ],
)
def test_bad_values_are_one_line_and_status_2(tmp_path, options, message):
    status, _, stderr = run(["render", "cornell", *options, *RENDER, "-o", "x.npy"], tmp_path)
    assert status == 2 and len(stderr.splitlines()) == 1 and message in stderr, stderr


@pytest.mark.gpu
def test_a_lightless_file_renders_lit_by_the_default_and_says_so(lightless_box, tmp_path):
    status, stdout, stderr = run(["render", str(lightless_box), *RENDER, "-o", "d.npy"], tmp_path)
    assert status == 0, stderr
    assert DEFAULT_NOTE in stdout
    image = load_image(tmp_path / "d.npy")
    assert image[0, 0] == pytest.approx([1.0, 1.0, 1.0]) and image.mean() > 0.5  # the sky of 1, the lit box


@pytest.mark.gpu
def test_env_none_renders_black(lightless_box, tmp_path):
    status, stdout, stderr = run(["render", str(lightless_box), "--env", "none", *RENDER, "-o", "n.npy"], tmp_path)
    assert status == 0 and "lighting" not in stdout, stderr
    assert load_image(tmp_path / "n.npy").max() == 0.0


@pytest.mark.gpu
@pytest.mark.parametrize(
    "options, radiance",
    [
        (["--env", "0.5"], (0.5, 0.5, 0.5)),
        (["--env", "1,0,0"], (1.0, 0.0, 0.0)),
        (["--env", "sky.exr", "--env-intensity", "2", "--env-rotation", "45"], (0.5, 0.5, 0.5)),
    ],
)
def test_a_constant_environment_or_map_seen_and_reflected(lightless_box, tmp_path, options, radiance):
    # Under BSDF sampling a convex grey box in a constant sky reflects exactly albedo x radiance:
    # every path escapes after one bounce. sky.exr is a map of 0.25 everywhere.
    save_image(tmp_path / "sky.exr", np.full((4, 8, 3), 0.25, np.float32))
    out = tmp_path / "c.npy"
    status, stdout, stderr = run(
        ["render", str(lightless_box), *options, "--integrator", "bsdf", *RENDER, "-o", str(out)], tmp_path
    )
    assert status == 0 and "lighting" not in stdout, stderr
    image = load_image(out).reshape(-1, 3)
    radiance = np.array(radiance, np.float32)
    seen = np.isclose(image, radiance, rtol=1e-6).all(axis=1)
    on_box = np.isclose(image, GREY * radiance, rtol=1e-5).all(axis=1)
    assert seen.any() and on_box.any()
    # the rest are pixels whose samples hit the box's edge and the sky alike: between the two
    edge = image[~(seen | on_box)]
    assert np.all((edge >= GREY * radiance - 1e-6) & (edge <= radiance + 1e-6))
