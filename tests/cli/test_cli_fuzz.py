"""The command line fuzzed: argument lists drawn from the real options with good and bad values
(garbage text, huge numbers, missing and broken files, unknown scenes), run in-process through
wgputrace.cli.main. Every run ends with 0, 1 or 2 and, unless 0, exactly one line on stderr that is
neither a traceback nor an internal error. Each render example is kept short by a small --size and
--time-limit appended last (argparse keeps the last value, but checks every one)."""

from __future__ import annotations

import contextlib
import io
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wgputrace import save_image
from wgputrace.cli import main
from wgputrace.provenance import read_metadata

pytestmark = pytest.mark.gpu  # renders and `info` open the adapter

EXAMPLES = 150
SHORT_RENDER = ["--size", "8x8", "--time-limit", "0.05"]

garbage = st.text(max_size=8)
# Files each example finds in its folder (made by `make_files`), and ones it does not
SCENE_FILES = ["garbage.obj", "raises.py", "missing.glb", "no_suffix", "folder"]
IMAGE_FILES = ["garbage.png", "garbage.exr", "no_metadata.npy", "missing.png", "folder"]
GOOD = {
    "--spp": st.integers(1, 40).map(str),
    "--time-limit": st.sampled_from(["0.01", "0.1", "1e-9"]),
    "--max-depth": st.sampled_from(["-1", "1", "2", "9", "40"]),
    "--seed": st.integers(-(2**70), 2**70).map(str),
    "--exposure": st.sampled_from(["0.1", "1", "-3.5", "1e3", "auto"]),
    "--tonemap": st.sampled_from(["clip", "pbr_neutral", "agx", "aces"]),
    "--size": st.sampled_from(["8x8", "3x5", "1X1"]),
    "--accel": st.sampled_from(["bvh", "flat"]),
    "--integrator": st.sampled_from(["bsdf", "nee", "mis"]),
    "-o": st.sampled_from(["out.png", "out.exr", "out.npy", "new/folder/out.npy", "OUT.PNG"]),
    "--env": st.sampled_from(["none", "0.5", "1,0,0", "0,0.2,1e3", "sky.exr"]),
    "--env-intensity": st.sampled_from(["0.5", "2", "1e-3"]),
    "--env-rotation": st.sampled_from(["-90", "0", "370.5"]),
}
BAD_NUMBERS = ["0", "-0", "-3", "1e400", "-1e400", "inf", "nan", "0x10", "9" * 30, "-" + "9" * 30]
BAD = {
    **dict.fromkeys(["--spp", "--time-limit", "--max-depth", "--seed", "--exposure"], st.sampled_from(BAD_NUMBERS)),
    "--size": st.sampled_from(["0x4", "4x-1", "axb", "99999x99999", "8", ""]),
    "--accel": st.sampled_from(["BVH", "kd"]),
    "--tonemap": st.sampled_from(["AgX", "filmic", ""]),
    "--integrator": st.sampled_from(["path", ""]),
    "-o": st.sampled_from(["out.jpg", "out", "folder", "garbage.png/out.png", "-"]),
    "--env": st.sampled_from(["-1", "nan", "1,2", "1,2,3,4", "inf,0,0", "missing.hdr", "folder", "garbage.exr", ""]),
    "--env-intensity": st.sampled_from(BAD_NUMBERS),
    "--env-rotation": st.sampled_from(["nan", "inf", "1e400", "x", ""]),
}


def options(values: dict) -> st.SearchStrategy[list[str]]:
    return st.sampled_from(sorted(values)).flatmap(lambda name: values[name].map(lambda value: [name, value]))


good_option = options(GOOD)
any_option = st.one_of(
    good_option,
    options(BAD),
    st.sampled_from(sorted(GOOD)).flatmap(lambda name: garbage.map(lambda value: [name, value])),
    st.sampled_from(
        [["--denoise"], ["--bogus"], ["--spp"], ["-o"], ["--help"], garbage.map(lambda word: [word])]
    ).flatmap(lambda words: words if isinstance(words, st.SearchStrategy) else st.just(words)),
)
good_scene = st.sampled_from(["cornell", "tiny_light", "axis_boxes", "glossy_spheres", "cornell_1e-4"])
any_scene = st.one_of(good_scene, st.sampled_from(["nowhere", *SCENE_FILES]), garbage)


def render_command(scene: st.SearchStrategy[str], option: st.SearchStrategy[list[str]]) -> st.SearchStrategy:
    words = st.tuples(st.lists(scene, max_size=1), st.lists(option, max_size=4))
    return words.map(lambda drawn: ["render", *drawn[0], *(word for pair in drawn[1] for word in pair), *SHORT_RENDER])


info_command = st.lists(st.sampled_from(IMAGE_FILES) | garbage, max_size=2).map(lambda files: ["info", *files])
command_line = st.one_of(
    render_command(good_scene, good_option),  # what a user means to type: mostly renders
    render_command(any_scene, any_option),
    info_command,
    st.lists(garbage, max_size=3),
)


def make_files(folder: Path) -> None:
    (folder / "garbage.obj").write_text("v 1 2\nf 1 2 3 4\nwhat\n")
    (folder / "raises.py").write_text("def scene():\n    raise RuntimeError('a scene script that fails')\n")
    (folder / "no_suffix").write_text("")
    (folder / "folder").mkdir()
    (folder / "garbage.png").write_bytes(b"\x89PNG not really")
    (folder / "garbage.exr").write_text("no EXR")
    (folder / "no_metadata.npy").write_bytes(b"\x93NUMPY")
    save_image(folder / "sky.exr", np.linspace(0, 2, 4 * 2 * 3, dtype=np.float32).reshape(2, 4, 3))


def run_in(folder: Path, argv: list[str]) -> tuple[int, str, str]:
    """main(argv) with `folder` as the working directory; (status, stdout, stderr)."""
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.chdir(folder), contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        status = main(argv)
    return status, stdout.getvalue(), stderr.getvalue()


def written_output(argv: list[str]) -> str:
    """The output a render command names last (argparse keeps the last -o), else the default."""
    named = [argv[index + 1] for index, word in enumerate(argv[:-1]) if word in ("-o", "--output")]
    return named[-1] if named else "render.png"


@pytest.mark.slow  # about 7 s on lavapipe
@settings(
    max_examples=EXAMPLES,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(argv=command_line)
def test_every_command_line_ends_in_a_known_status_and_one_line(argv):
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        make_files(folder)
        status, stdout, stderr = run_in(folder, argv)
        assert status in (0, 1, 2), (argv, status, stderr)
        if status:
            assert len(stderr.splitlines()) == 1, (argv, stderr)
            assert "Traceback" not in stderr and "internal error" not in stderr, (argv, stderr)
        elif argv[:1] == ["render"] and "--help" not in argv:
            assert read_metadata(folder / written_output(argv)), argv


def test_a_bad_argument_is_one_line_and_status_2(run_cli):
    result = run_cli("render", "--spp", "-3")
    assert result.returncode == 2
    assert result.stderr == (
        "wgputrace render: error: argument --spp: must be at least 1, got '-3' (see wgputrace render --help)\n"
    )
