"""KernelVariant is the one statement of what a kernel compiles in: every feature it names changes
the generated files or the bind groups, equal variants are one cached kernel, and a variant that
cannot exist (rows under an integrator without a band-of-rows kernel, an unknown sampler or
acceleration) is refused in one line."""

from __future__ import annotations

from dataclasses import fields, replace

import pytest

from wgputrace import Camera, Diffuse, PointLight, Principled, Scene, make_box
from wgputrace.integrators import integrator
from wgputrace.kernels.compile import tracing_kernel
from wgputrace.kernels.hooks import HOOKS
from wgputrace.kernels.light_dispatch import LightFeatures
from wgputrace.kernels.principled_lobes import GENERATED_PRINCIPLED_LOBES, LOBE_SHADERS
from wgputrace.kernels.textures import GENERATED_TEXTURES
from wgputrace.kernels.variant import DEFAULT_VARIANT, KernelVariant, SceneFeatures
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.scene.materials.principled import PRINCIPLED_LOBES

MIS = KernelVariant(integrator=integrator("mis"))


def boolean_fields(value) -> list[str]:
    return [f.name for f in fields(value) if f.type == "bool"]


def test_every_hook_file_is_generated_for_every_variant():
    assert set(HOOKS) <= set(DEFAULT_VARIANT.files())
    assert set(HOOKS) <= set(MIS.files())


@pytest.mark.parametrize("name", boolean_fields(SceneFeatures))
def test_each_scene_feature_changes_what_is_compiled(name):
    on = KernelVariant(replace(SceneFeatures(), **{name: True}), integrator("mis"))
    changed = {file for file, text in on.files().items() if MIS.files()[file] != text}
    groups_changed = on.groups() != MIS.groups()
    assert changed or groups_changed, f"SceneFeatures.{name} compiles in nothing"
    assert on != MIS and hash(on) != hash(MIS)
    assert on.label != MIS.label, "the label names every feature that is on"


@pytest.mark.parametrize("name", boolean_fields(KernelVariant))
def test_each_kernel_option_changes_what_is_compiled(name):
    # a pre-pass is restir's alone
    base = replace(MIS, integrator=integrator("restir")) if name == "prepass" else MIS
    on = replace(base, **{name: True})
    files_changed = on.files() != base.files()
    assert files_changed or on.groups() != base.groups() or on.entry != base.entry
    assert on.label != base.label


def test_only_restir_sharing_reservoirs_runs_a_prepass_and_one_sample_per_dispatch():
    restir = KernelVariant(integrator=integrator("restir"), samples_per_dispatch=8)
    sharing = integrator("restir").with_overrides({"RESERVOIR_NEIGHBOURS": 3})
    shared = KernelVariant(integrator=sharing, overrides=(("RESERVOIR_NEIGHBOURS", 3.0),), samples_per_dispatch=8)
    assert integrator("restir").pixel_arrays == () and {a.binding.name for a in sharing.pixel_arrays} == {
        "restir_reservoirs",
        "restir_receivers",
    }
    assert not restir.integrator.uses_prepass(restir) and restir.samples_per_dispatch == 8
    assert shared.integrator.uses_prepass(shared) and shared.samples_per_dispatch == 1
    first_vertex = "generated/first_vertex_light.wgsl"
    assert "restir/shared_reservoirs.wgsl" in shared.files()[first_vertex]
    assert "restir/own_reservoir.wgsl" in restir.files()[first_vertex]
    # the viewer's bands trace part of the image: no pre-pass, no sharing
    rows = replace(shared, rows=True)
    assert not rows.integrator.uses_prepass(rows)
    assert "restir/own_reservoir.wgsl" in rows.files()[first_vertex]
    assert shared.entry[1] == "main" and replace(shared, prepass=True).entry == (
        "integrators/restir/candidates.wgsl",
        "main_prepass",
    )
    with pytest.raises(ValueError, match="the mis integrator has no pre-pass"):
        replace(MIS, prepass=True)


def test_lights_choose_the_lights_group_and_its_bindings():
    assert "lights" not in {group.name for group in MIS.groups()}
    points = MIS.with_scene(SceneFeatures(lights=LightFeatures((PointLight.kind,))))
    lights = next(group for group in points.groups() if group.name == "lights")
    assert [binding.name for binding in lights.bindings] == ["lighting", "light_sources"]
    assert "PointLight" in points.label


def test_the_pixels_group_has_the_guides_and_the_integrators_arrays():
    names = lambda variant: [binding.name for binding in variant.pixels_group().bindings]  # noqa: E731
    assert names(MIS) == ["rng_states", "accumulation"]
    assert names(replace(MIS, guides=True)) == ["rng_states", "accumulation", "guide_sums"]
    bdpt = replace(MIS, integrator=integrator("bdpt"), guides=True)
    assert names(bdpt) == ["rng_states", "accumulation", "guide_sums", "splats"]


def test_overrides_are_one_key_whatever_their_order():
    a = replace(MIS, overrides=(("B", 1.0), ("A", 2.0)))
    b = replace(MIS, overrides=(("A", 2.0), ("B", 1.0)))
    assert a == b and hash(a) == hash(b)
    assert a.constants == {"INTEGRATOR": 2, "A": 2.0, "B": 1.0}


def test_impossible_variants_are_refused_in_one_line():
    with pytest.raises(ValueError, match="bdpt integrator renders whole images only"):
        KernelVariant(integrator=integrator("bdpt"), rows=True)
    with pytest.raises(ValueError, match="sampler must be one of independent, sobol, got 'halton'"):
        KernelVariant(sampler="halton")
    with pytest.raises(ValueError, match="acceleration must be one of"):
        SceneFeatures(acceleration="octree")
    with pytest.raises(ValueError, match="names no integrator"):
        _ = DEFAULT_VARIANT.entry


def test_regeneration_binds_the_dispatch_group_and_names_its_count():
    several = replace(MIS, samples_per_dispatch=8)
    assert "dispatch" in {group.name for group in several.groups()} - {group.name for group in MIS.groups()}
    assert "8 samples per dispatch" in several.label and "per dispatch" not in MIS.label
    assert several.files() != MIS.files()
    # the viewer's bands take one sample per pixel whatever the renderer's kernel takes, none owed
    bands = replace(several, loop_budget=True, rows=True)
    assert bands.samples_per_dispatch == 1 and not bands.loop_budget
    with pytest.raises(ValueError, match="bdpt integrator's kernel takes one sample"):
        replace(several, integrator=integrator("bdpt"))
    with pytest.raises(ValueError, match="at least 1"):
        replace(MIS, samples_per_dispatch=0)


def test_the_mirror_states_the_scenes_part():
    lamp = make_box((0, 1, 0), (0, 0, 0), (0.2, 0.01, 0.2), Diffuse("lamp"), "lamp")
    scene = Scene([lamp], Camera())
    features = SceneMirror(scene, "bvh").features
    assert features.material_kinds == (Diffuse.kind,) and not features.lights.any and features.lobes == ()
    scene.add_light(PointLight((0, 2, 0), 1.0))
    assert SceneMirror(scene, "flat").features.lights.kinds == (PointLight.kind,)


@pytest.mark.parametrize("lobe", PRINCIPLED_LOBES)
def test_a_principled_lobe_is_compiled_only_for_scenes_that_use_it(lobe):
    coated = Principled("coated", **{lobe: 0.5})
    scene = Scene([make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), coated, "box")], Camera())
    used = KernelVariant(SceneMirror(scene, "bvh").features, integrator("mis"))
    assert used.scene.lobes == (lobe,) and f"{lobe} lobe" in used.label
    file = LOBE_SHADERS[lobe][0]
    assert f'//! include "{file}"' in used.files()[GENERATED_PRINCIPLED_LOBES]
    setattr(coated, lobe, 0.0)
    unused = KernelVariant(SceneMirror(scene, "bvh").features, integrator("mis"))
    assert file not in unused.files()[GENERATED_PRINCIPLED_LOBES] and f"{lobe} lobe" not in unused.label
    with pytest.raises(ValueError, match="unknown material lobes"):
        SceneFeatures(lobes=("iridescence",))


def test_the_bsdf_frame_follows_the_tangents_only_in_scenes_with_anisotropy():
    brushed = Principled("brushed", metallic=1.0, anisotropic=0.5)
    scene = Scene([make_box((0, 0, 0), (0, 0, 0), (1, 1, 1), brushed, "box")], Camera())
    used = KernelVariant(SceneMirror(scene, "bvh").features, integrator("mis"))
    # the tangents come with the texture records: an anisotropic scene is a textured one
    assert used.scene.textured and '//! include "shading/surface_frame.wgsl"' in used.files()[GENERATED_TEXTURES]
    brushed.anisotropic = 0.0
    unused = KernelVariant(SceneMirror(scene, "bvh").features, integrator("mis"))
    assert not unused.scene.textured and "surface_frame.wgsl" not in unused.files()[GENERATED_TEXTURES]


@pytest.mark.gpu
def test_equal_variants_are_one_compiled_kernel(gpu_context):
    first = tracing_kernel(gpu_context, MIS)
    assert tracing_kernel(gpu_context, KernelVariant(integrator=integrator("mis"))) is first
    assert tracing_kernel(gpu_context, replace(MIS, count_rays=True)) is not first
    assert "ray_counts" in tracing_kernel(gpu_context, replace(MIS, count_rays=True)).source.text
