"""A scene file's cameras on the command line: `wgputrace info model.glb` lists them (index, name,
kind, pose and parameters), `--camera NAME|INDEX` chooses one for `render` and `view`, and one
that is not there is a one-line error listing those there are."""

from __future__ import annotations

import pytest

from wgputrace.app import options_from
from wgputrace.cli import argument_parser
from wgputrace.provenance import NAMESPACE, read_metadata
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, box_with_cameras, gltf_document, write_glb


def test_info_lists_the_cameras_of_a_scene_file(tmp_path, run_cli):
    path = box_with_cameras(tmp_path / "box.glb")
    result = run_cli("info", str(path))
    assert result.returncode == 0, result.stderr
    title, front, top = result.stdout.splitlines()
    assert title == f"{path}: 12 triangles, 2 cameras"
    assert front == "  0  'front'  Camera: position 0,0.5,6, forward 0,0,-1, up 0,1,0, vfov_degrees 40.1070457"
    # the quarter turn's rounding leaves 2e-16 where 0 would be
    assert top.startswith("  1  'top'  OrthographicCamera: position 0,5,0, forward 0,-1,") and top.endswith(
        ", view_height 3"
    )


def test_info_of_a_file_without_cameras_says_it_is_framed(tmp_path, run_cli):
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    path = write_glb(tmp_path / "plain.glb", document, blob)
    result = run_cli("info", str(path))
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[0] == f"{path}: 12 triangles, 0 cameras"
    assert result.stdout.splitlines()[1].startswith("  no camera of its own: framed automatically (Camera: position")


def test_an_unknown_camera_is_one_line_listing_the_cameras(tmp_path, run_cli):
    path = box_with_cameras(tmp_path / "box.glb")
    result = run_cli("render", str(path), "--camera", "side", "--size", "8x8", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2
    assert result.stderr == f"wgputrace: error: {path}: no camera 'side'; its cameras: 0 'front', 1 'top'\n"
    assert not (tmp_path / "x.png").exists()


def test_view_takes_the_camera_option():
    args = argument_parser().parse_args(["view", "box.glb", "--camera", "top"])
    assert options_from(args).camera == "top"


@pytest.mark.gpu
@pytest.mark.parametrize(("choice", "kind"), [("top", "OrthographicCamera"), ("0", "Camera")])
def test_render_from_a_chosen_camera(tmp_path, run_cli, choice, kind):
    path = box_with_cameras(tmp_path / "box.glb")
    out = tmp_path / "chosen.png"
    result = run_cli("render", str(path), "--camera", choice, "--spp", "1", "--size", "16x12", "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert read_metadata(out)[NAMESPACE + "camera"].startswith(f"{kind}: ")
