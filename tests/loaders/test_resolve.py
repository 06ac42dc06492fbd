"""wgputrace.load_scene, the one resolver: a built-in name, a scene file or a .py file defining
scene(); a path that does not exist, an unknown name and an unsupported suffix each get their own
message, and a broken .py file names its file and line."""

from __future__ import annotations

from pathlib import Path

import pytest

from wgputrace import Camera, SceneLoadError, load_scene
from wgputrace.loaders import FORMATS, scene_file
from wgputrace.scenes import BUILTIN_SCENES

LAMP = """import wgputrace as wt


def scene():
    lamp = wt.Emitter("lamp")
    return wt.Scene([wt.make_plane((0, 0, 2), (-1.5707963, 0, 0), (1, 1), lamp, "lamp")])
"""
# one triangle, its own material
TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"


def test_a_builtin_name_a_scene_file_and_a_python_file_load(tmp_path):
    assert load_scene("tiny_light").triangle_count == 676
    (tmp_path / "triangle.obj").write_text(TRIANGLE_OBJ)
    assert load_scene(str(tmp_path / "triangle.obj")).triangle_count == 1
    assert load_scene(tmp_path / "triangle.obj").triangle_count == 1
    (tmp_path / "lamp.py").write_text(LAMP)
    assert load_scene(str(tmp_path / "lamp.py")).triangle_count == 2


def test_a_relative_python_file_loads_from_the_working_directory(tmp_path, monkeypatch):
    (tmp_path / "lamp.py").write_text(LAMP)
    monkeypatch.chdir(tmp_path)
    assert load_scene("lamp.py").triangle_count == 2


def test_camera_replaces_the_scenes_camera_for_every_kind(tmp_path):
    camera = Camera.looking_at((3, 4, 5), (0, 0, 0))
    (tmp_path / "triangle.obj").write_text(TRIANGLE_OBJ)
    (tmp_path / "lamp.py").write_text(LAMP)
    for spec in ("cornell", str(tmp_path / "triangle.obj"), str(tmp_path / "lamp.py")):
        assert load_scene(spec, camera=camera).camera is camera


def test_what_names_a_file():
    assert scene_file("cornell") is None and scene_file("kitchen") is None
    assert scene_file("cornell_1e-4") is None
    assert scene_file("model.glb") == Path("model.glb")
    assert scene_file("scenes/kitchen") == Path("scenes/kitchen")
    assert scene_file(Path("cornell")) == Path("cornell")


@pytest.mark.parametrize(
    "source, message",
    [
        ("import wgputrace\n\ndef scene(:\n", r"broken\.py:3: SyntaxError"),
        ("def scene():\n    x = 1\n    return 1 / 0\n", r"broken\.py:3: ZeroDivisionError: division by zero"),
        ("import wgputrace\n\nwgputrace.nothing\n", r"broken\.py:3: AttributeError: .*nothing"),
        ("x = 1\n", r"broken\.py: defines no function scene\(\)"),
        ("def scene():\n    return 42\n", r"broken\.py: scene\(\) returned int, not a wgputrace\.Scene"),
        (
            "import wgputrace as wt\ndef scene():\n    return wt.Scene()\n",
            r"broken\.py: SceneError: the scene has no triangles",
        ),
    ],
)
def test_a_broken_python_file_names_file_line_and_problem(tmp_path, source, message):
    path = tmp_path / "broken.py"
    path.write_text(source)
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(str(path))
    assert caught.value.path == path


@pytest.mark.parametrize("name", ["nowhere.py", "nowhere.obj", "nowhere.glb", "sub/nowhere.stl"])
def test_a_path_that_does_not_exist_is_no_such_file(tmp_path, name):
    with pytest.raises(SceneLoadError) as caught:
        load_scene(str(tmp_path / name))
    assert str(caught.value) == f"{tmp_path / name}: no such file"
    assert "built-in" not in str(caught.value)


def test_a_mistyped_relative_path_is_no_such_file_too(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SceneLoadError, match=r"^models/cornel\.obj: no such file$"):
        load_scene("models/cornel.obj")
    with pytest.raises(SceneLoadError, match=r"^cornel\.glb: no such file$"):
        load_scene("cornel.glb")


def test_an_unknown_name_lists_the_builtin_scenes():
    with pytest.raises(SceneLoadError) as caught:
        load_scene("kitchen")
    message = str(caught.value)
    assert message.startswith("unknown scene 'kitchen'; built-in scenes: ")
    assert all(name in message for name in BUILTIN_SCENES)
    assert caught.value.path is None


def test_an_unsupported_suffix_names_the_supported_ones(tmp_path):
    (tmp_path / "model.fbx").write_text("not read")
    with pytest.raises(SceneLoadError) as caught:
        load_scene(str(tmp_path / "model.fbx"))
    assert str(caught.value) == (
        f"{tmp_path / 'model.fbx'}: unknown scene format '.fbx'; wgputrace reads {', '.join(FORMATS)}"
    )
    assert {".obj", ".gltf", ".glb", ".ply", ".stl", ".py"} == set(FORMATS)
    # a folder, or a mistyped path without a suffix, is told what a scene file looks like
    with pytest.raises(SceneLoadError, match=r"scenes: no file suffix; wgputrace reads \.obj"):
        load_scene(str(tmp_path / "scenes"))
