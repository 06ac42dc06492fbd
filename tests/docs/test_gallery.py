"""The gallery (docs/gallery) runs: each script, at a tiny size (every render TINY_SIZE pixels at
TINY_SPP samples per pixel, whatever the script asks), saves pictures that are finite and not
black, as the site's build would show them; and together the scripts show every built-in scene.
Sphinx is not needed: the scripts are plain programs."""

from __future__ import annotations

import ast
import runpy
from pathlib import Path

import numpy as np
import pytest

import wgputrace
from wgputrace.scenes import BUILTIN_SCENES

pytestmark = pytest.mark.gpu

GALLERY = Path(__file__).resolve().parents[2] / "docs" / "gallery"
SCRIPTS = sorted(GALLERY.rglob("*.py"))
TINY_SIZE = (24, 18)
TINY_SPP = 2


class TinyRenderer(wgputrace.Renderer):
    """A Renderer whatever size it is asked for renders TINY_SIZE, at most TINY_SPP per call."""

    def __init__(self, scene, width=None, height=None, **options) -> None:
        super().__init__(scene, *TINY_SIZE, **options)

    def render(self, spp=None, *args, **options):
        return super().render(min(spp, TINY_SPP) if spp is not None else None, *args, **options)


@pytest.fixture
def tiny_renders(monkeypatch: pytest.MonkeyPatch) -> None:
    render = wgputrace.render

    def tiny_render(scene, spp=None, width=None, height=None, **options):
        return render(scene, spp=TINY_SPP, width=TINY_SIZE[0], height=TINY_SIZE[1], **options)

    monkeypatch.setattr(wgputrace, "render", tiny_render)
    monkeypatch.setattr(wgputrace, "Renderer", TinyRenderer)


@pytest.fixture
def saved_images(monkeypatch: pytest.MonkeyPatch) -> dict[str, np.ndarray]:
    """What the script saves with wgputrace.save_image, by file name (and saved to the file too)."""
    saved = {}
    save_image = wgputrace.save_image

    def recording_save_image(path, image, *args, **options):
        saved[str(path)] = np.array(image)
        return save_image(path, image, *args, **options)

    monkeypatch.setattr(wgputrace, "save_image", recording_save_image)
    return saved


@pytest.mark.parametrize("script", SCRIPTS, ids=[str(s.relative_to(GALLERY)) for s in SCRIPTS])
def test_gallery_script_saves_its_pictures(script, tmp_path, monkeypatch, tiny_renders, saved_images):
    monkeypatch.chdir(tmp_path)
    try:
        runpy.run_path(str(script), run_name="__main__")
    except wgputrace.DenoiserMissing as error:
        pytest.skip(f"{script.name} denoises: {error}")
    assert saved_images, f"{script.name} saved no picture"
    for name, image in saved_images.items():
        assert image.shape == (TINY_SIZE[1], TINY_SIZE[0], 3), name
        assert np.isfinite(image).all(), f"{script.name}: {name} has non-finite pixels"
        assert image.max() > 0, f"{script.name}: {name} is black"
        assert (tmp_path / name).is_file(), name


def _scene_names(script: Path) -> set[str]:
    """The built-in scene names a script passes to load_scene."""
    calls = (node for node in ast.walk(ast.parse(script.read_text())) if isinstance(node, ast.Call))
    return {
        call.args[0].value
        for call in calls
        if getattr(call.func, "attr", None) == "load_scene" and call.args and isinstance(call.args[0], ast.Constant)
    }


def test_gallery_shows_every_builtin_scene():
    shown = set().union(*(_scene_names(script) for script in SCRIPTS))
    assert set(BUILTIN_SCENES) <= shown, f"no gallery script shows {sorted(set(BUILTIN_SCENES) - shown)}"
