"""The camera kind in a kernel variant (`SceneFeatures.camera`): each kind compiles its own WGSL
into generated/camera.wgsl, names itself in the kernel's label (the pinhole does not: labels of
today's kernels stay as they were), comes from the scene's camera, and an unknown kind is refused."""

from __future__ import annotations

import pytest

from wgputrace import Diffuse, Scene, make_box
from wgputrace.integrators import integrator
from wgputrace.kernels.camera import DEFAULT_CAMERA, GENERATED_CAMERA
from wgputrace.kernels.variant import KernelVariant, SceneFeatures
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.scene import Camera, EquirectangularCamera, OrthographicCamera, ThinLensCamera, camera_classes

MIS = integrator("mis")


@pytest.mark.parametrize("cls", camera_classes(), ids=lambda cls: cls.__name__)
def test_each_kind_compiles_its_own_wgsl_and_names_itself(cls):
    variant = KernelVariant(SceneFeatures(camera=cls.kind), MIS)
    assert f'//! include "{cls.shader}"' in variant.files()[GENERATED_CAMERA]
    assert (cls.__name__ in variant.label) == (cls.kind != DEFAULT_CAMERA)
    assert DEFAULT_CAMERA == Camera.kind and "Camera" not in KernelVariant(SceneFeatures(), MIS).label


@pytest.mark.parametrize(
    "camera",
    [
        Camera(),
        ThinLensCamera(aperture_radius=0.1, focus_distance=2.0),
        OrthographicCamera(view_height=2.0),
        EquirectangularCamera(),
    ],
    ids=lambda camera: type(camera).__name__,
)
def test_the_scene_decides_the_kind(camera):
    scene = Scene([make_box((0, 0, 3), (0, 0, 0), (1, 1, 1), Diffuse("white"))], camera)
    assert SceneMirror(scene, "bvh").features.camera == camera.kind


def test_an_unknown_kind_is_refused_by_name():
    with pytest.raises(
        ValueError, match="no camera kind 9 is registered; the kinds are 1 \\(Camera\\), 2 \\(ThinLensCamera\\)"
    ):
        SceneFeatures(camera=9)
