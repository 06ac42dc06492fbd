"""The absorption hook: only kernels for scenes with an absorbing material read the records'
absorption, so every other scene's kernel stays as it was."""

from __future__ import annotations

from wgputrace.kernels.absorption import absorption_hook
from wgputrace.kernels.variant import KernelVariant, SceneFeatures


def test_only_absorbing_scenes_compile_absorption_in():
    plain = absorption_hook(KernelVariant())
    assert "absorption" not in plain.split("\n", 1)[1] and "return vec3<f32>(1.0);" in plain
    absorbing = KernelVariant(SceneFeatures(absorbing=True))
    assert '//! include "shading/absorption.wgsl"' in absorption_hook(absorbing)
    assert "absorbing" in absorbing.label and "absorbing" not in KernelVariant().label
