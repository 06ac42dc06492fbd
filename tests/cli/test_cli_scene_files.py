"""`wgputrace render FILE`: scene files on the command line, the GPU memory line, load errors; and
`render` and `view` read SCENE through the same resolver, so each accepts what the other does."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import load_image

# a lit box in front of the default camera (at the origin, looking along +z)
LIT_BOX = """import wgputrace as wt


def scene():
    lamp = wt.make_icosphere((0, 1, 4), (0, 0, 0), 0.5, 1, wt.Emitter("lamp"), "lamp")
    return wt.Scene([lamp, wt.make_box((0, -1, 4), (0, 0.5, 0), (1, 1, 1), wt.Diffuse("white"), "box")])
"""


def scene_spec(kind: str, tmp_path, data_dir) -> tuple[str, int]:
    """SCENE of each kind, with its triangle count."""
    if kind == "py":
        (tmp_path / "lit_box.py").write_text(LIT_BOX)
        return str(tmp_path / "lit_box.py"), 92
    return ("tiny_light", 676) if kind == "name" else (str(data_dir / "cornell_trac0r.obj"), 676)


@pytest.mark.gpu
def test_render_a_scene_file(tmp_path, data_dir, run_cli):
    out = tmp_path / "obj.npy"
    result = run_cli("render", str(data_dir / "cornell_trac0r.obj"), "--spp", "1", "--size", "16x12", "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert load_image(out).shape == (12, 16, 3) and np.all(np.isfinite(load_image(out)))
    assert "676 triangles, 6 materials, loaded in" in result.stdout
    assert "B per triangle (triangles, BVH nodes, materials, lights" in result.stdout


def test_a_broken_scene_file_is_named_with_its_line(tmp_path, run_cli):
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nf 1 2 3\n")
    result = run_cli("render", str(broken), "--spp", "1", "--size", "8x8", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2
    assert f"wgputrace: error: {broken}:3: face vertex index 3 is out of range: 2 vertices" in result.stderr


@pytest.mark.gpu
def test_render_a_python_scene(tmp_path, data_dir, run_cli):
    spec, triangles = scene_spec("py", tmp_path, data_dir)
    out = tmp_path / "lit_box.npy"
    result = run_cli("render", spec, "--spp", "1", "--size", "16x12", "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert f"lit_box.py: {triangles} triangles, 2 materials" in result.stdout
    assert load_image(out).max() > 0


def test_a_broken_python_scene_is_named_with_its_line(tmp_path, run_cli):
    broken = tmp_path / "broken.py"
    broken.write_text("import wgputrace as wt\n\n\ndef scene():\n    return wt.make_box()\n")
    result = run_cli("render", str(broken), "--spp", "1", "--size", "8x8", "-o", str(tmp_path / "x.png"))
    assert result.returncode == 2 and f"wgputrace: error: {broken}:5: TypeError" in result.stderr


@pytest.mark.gpu
@pytest.mark.filterwarnings("ignore::wgputrace.SceneLoadWarning")  # the trac0r OBJ's inward boxes
@pytest.mark.parametrize("kind", ["name", "obj", "py"])
def test_view_loads_what_render_loads(gpu_context, tmp_path, data_dir, kind):
    from wgputrace.app import options_from
    from wgputrace.app.viewer import Viewer
    from wgputrace.app.window import create_canvas
    from wgputrace.cli import argument_parser

    spec, triangles = scene_spec(kind, tmp_path, data_dir)
    args = argument_parser().parse_args(["view", spec, "--size", "16x12", "--screenshots", str(tmp_path)])
    viewer = Viewer(create_canvas(args.size, "test", offscreen=True), options_from(args))
    assert viewer.errors == [] and viewer.scene.triangle_count == triangles
