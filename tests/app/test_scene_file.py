"""Scene files for the viewer: errors name the file and line, built-in names still work."""

from __future__ import annotations

import pytest

from wgputrace.app.scene_file import SceneLoadError, load_scene, modified_time

GOOD = """import wgputrace as wt


def scene():
    lamp = wt.Emitter("lamp")
    return wt.Scene([wt.make_plane((0, 0, 2), (-1.5707963, 0, 0), (1, 1), lamp, "lamp")])
"""


def test_a_python_scene_file_loads(tmp_path):
    path = tmp_path / "lamp.py"
    path.write_text(GOOD)
    assert load_scene(str(path)).triangle_count == 2
    assert modified_time(str(path)) == path.stat().st_mtime
    assert modified_time("cornell") is None


@pytest.mark.parametrize(
    "source, message",
    [
        ("import wgputrace\n\ndef scene(:\n", r"broken\.py:3: SyntaxError"),
        ("def scene():\n    x = 1\n    return 1 / 0\n", r"broken\.py:3: ZeroDivisionError: division by zero"),
        ("x = 1\n", r"broken\.py: defines no function scene\(\)"),
        ("def scene():\n    return 42\n", r"broken\.py: scene\(\) returned int, not a wgputrace\.Scene"),
        (
            "import wgputrace as wt\ndef scene():\n    return wt.Scene()\n",
            r"broken\.py: SceneError: the scene has no triangles",
        ),
    ],
)
def test_a_broken_scene_file_names_file_line_and_problem(tmp_path, source, message):
    path = tmp_path / "broken.py"
    path.write_text(source)
    with pytest.raises(SceneLoadError, match=message):
        load_scene(str(path))


def test_missing_files_and_unknown_names_are_named(tmp_path):
    with pytest.raises(SceneLoadError, match="nowhere.py: cannot read the scene file"):
        load_scene(str(tmp_path / "nowhere.py"))
    with pytest.raises(SceneLoadError, match="unknown scene 'kitchen'"):
        load_scene("kitchen")
    with pytest.raises(SceneLoadError, match="nowhere.obj"):
        load_scene(str(tmp_path / "nowhere.obj"))
