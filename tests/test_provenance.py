"""Provenance: what a render records about itself, read back from each image format, and how
`wgputrace info FILE` prints it."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

from wgputrace import (
    Camera,
    DirectionalLight,
    Environment,
    PointLight,
    Renderer,
    __version__,
    default_scene,
    save_image,
)
from wgputrace.image_io import FORMATS, sidecar_path
from wgputrace.provenance import KEYS, NAMESPACE, format_metadata, read_metadata, render_metadata

SIZE = (8, 6)
SEED = 5
SPP = 2


@pytest.fixture(scope="module")
def renderer(gpu_context):
    renderer = Renderer(default_scene(), *SIZE, seed=SEED)
    renderer.render(SPP)
    return renderer


def ours(metadata: dict[str, str]) -> dict[str, str]:
    return {key.removeprefix(NAMESPACE): value for key, value in metadata.items()}


def test_a_render_records_how_it_was_made(renderer):
    recorded = ours(render_metadata(renderer, "cornell", 1.25, stopped_by="SIGINT"))
    # a built-in scene: the version fixes it; the denoiser's keys are the command line's to add, and
    # a PNG's tone mapping is the PNG writer's
    assert set(recorded) == set(KEYS) - {"scene_sha256", "denoised", "denoiser_device", "tonemap", "exposure"}
    assert (recorded["width"], recorded["height"]) == tuple(map(str, SIZE))
    assert (recorded["spp"], recorded["seed"], recorded["scene"]) == (str(SPP), str(SEED), "cornell")
    assert (recorded["integrator"], recorded["max_depth"], recorded["accel"]) == ("mis", "9", "bvh")
    assert recorded["adapter"] == renderer.context.adapter.info["device"]
    assert (recorded["render_seconds"], recorded["stopped_by"]) == ("1.250", "SIGINT")
    assert recorded["nonfinite_samples"] == str(renderer.nonfinite_samples)
    assert recorded["date"].endswith("+00:00")
    assert recorded["version"] == __version__  # the installed distribution's, as the package says
    assert "stopped_by" not in ours(render_metadata(renderer, "cornell", 1.0))


def test_a_scene_file_is_named_and_hashed(renderer, tmp_path):
    scene = tmp_path / "room.obj"
    scene.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    recorded = ours(render_metadata(renderer, str(scene), 1.0))
    assert recorded["scene"] == "room.obj"
    assert recorded["scene_sha256"] == hashlib.sha256(scene.read_bytes()).hexdigest()


def test_a_python_scene_hashes_as_rendered(renderer, gpu_context):
    def scene_hash(renderer):
        return ours(render_metadata(renderer, None, 1.0))["scene_sha256"]

    scene = default_scene()
    edited = Renderer(scene, *SIZE, seed=SEED)
    assert scene_hash(edited) == scene_hash(renderer)  # equal scenes, other Renderers
    scene.materials[0].color = (0.1, 0.2, 0.3)
    edited.update()
    changed = scene_hash(edited)
    assert changed != scene_hash(renderer)
    scene.camera = Camera(position=(0.0, 0.5, -2.0))
    edited.update()
    assert scene_hash(edited) not in (changed, scene_hash(renderer))


@pytest.mark.parametrize("suffix", FORMATS)
def test_metadata_comes_back_from_every_format(renderer, tmp_path, suffix):
    metadata = render_metadata(renderer, None, 0.5)
    path = save_image(tmp_path / f"out{suffix}", renderer.image(), metadata=metadata)
    read = read_metadata(path)
    assert read == metadata
    assert [key.removeprefix(NAMESPACE) for key in read] == [key for key in KEYS if NAMESPACE + key in metadata]


def test_a_file_without_our_metadata_is_named(tmp_path):
    image = np.zeros((2, 2, 3), np.float32)
    with pytest.raises(ValueError, match=r"absent\.png: no such file"):
        read_metadata(tmp_path / "absent.png")
    with pytest.raises(ValueError, match=r"other\.png: has no wgputrace metadata \(written elsewhere"):
        read_metadata(save_image(tmp_path / "other.png", image, metadata={"Software": "GIMP"}))
    npy = save_image(tmp_path / "x.npy", image)
    with pytest.raises(ValueError, match=r"x\.npy: has no wgputrace metadata \(no x\.npy\.json beside it\)"):
        read_metadata(npy)
    assert not sidecar_path(npy).exists()


def test_metadata_prints_as_aligned_lines():
    metadata = {NAMESPACE + "spp": "64", NAMESPACE + "render_seconds": "1.500", "other:key": "x"}
    assert format_metadata(metadata).splitlines() == [
        "spp             64",
        "render_seconds  1.500",
        "other:key       x",
    ]
    assert format_metadata({}) == ""


def test_the_lighting_is_recorded(gpu_context):
    scene = default_scene()
    texels = np.full((3, 4, 3), 0.25, np.float32)
    scene.environment = Environment(texels=texels, intensity=2.0, rotation_degrees=30.0, visible=False)
    scene.add_light(PointLight((0.0, 0.5, 0.0), 1.0), PointLight((0.1, 0.5, 0.0), 1.0))
    scene.add_light(DirectionalLight((0.0, -1.0, 0.0), 1.0))
    lit = Renderer(scene, *SIZE, seed=SEED)
    lit.render(1)
    recorded = ours(render_metadata(lit, None, 0.5))
    assert recorded["lights"] == "1 DirectionalLight, 2 PointLight"
    digest = hashlib.sha256(texels.tobytes()).hexdigest()
    assert digest in recorded["environment"] and "4x3" in recorded["environment"]
    assert "intensity 2" in recorded["environment"] and "rotation 30" in recorded["environment"]
    assert "hidden" in recorded["environment"]


def test_no_lighting_besides_triangles_says_none(renderer):
    recorded = ours(render_metadata(renderer, "cornell", 1.0))
    assert (recorded["environment"], recorded["lights"]) == ("none", "none")
