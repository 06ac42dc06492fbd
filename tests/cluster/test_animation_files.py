"""Scene files that define scene(frame): read one frame at a time, from a file or its text; a still
of them is frame 0, and a still file asked for a frame says it has none."""

from __future__ import annotations

import pytest

from wgputrace import SceneLoadError, load_scene
from wgputrace.loaders.python_scene import read_python_scene, scene_from_source

ANIMATION = """
import wgputrace as wt

def scene(frame):
    if frame == 13:
        raise RuntimeError("unlucky frame")
    scene = wt.default_scene()
    scene.camera = wt.Camera.looking_at((0.1 * frame, 1, -3), (0, 0.3, 0), vfov_degrees=45)
    return scene
"""
STILL = "import wgputrace as wt\n\ndef scene():\n    return wt.default_scene()\n"


@pytest.fixture
def animation(tmp_path):
    path = tmp_path / "animation.py"
    path.write_text(ANIMATION)
    return path


def test_each_frame_is_the_functions_scene_of_it(animation):
    assert read_python_scene(animation, 4).camera.position[0] == pytest.approx(0.4)
    assert scene_from_source(ANIMATION, animation, 2).camera.position[0] == pytest.approx(0.2)


def test_an_animation_loaded_as_a_still_is_its_frame_0(animation):
    assert load_scene(animation).camera.position[0] == pytest.approx(0.0)


def test_a_failing_frame_names_the_file_and_line(animation):
    with pytest.raises(SceneLoadError, match=r"animation.py:6: RuntimeError: unlucky frame"):
        read_python_scene(animation, 13)


def test_a_still_has_no_frames(tmp_path):
    path = tmp_path / "still.py"
    path.write_text(STILL)
    assert read_python_scene(path).triangle_count > 0
    with pytest.raises(SceneLoadError, match=r"still.py: defines scene\(\) without a frame parameter"):
        read_python_scene(path, 1)
