"""Material kinds as descriptors: the registry, the code generated from it, and a new kind added
as one Python file and one WGSL file, rendered through the real Renderer."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import wgputrace
from wgputrace.gpu.shader_source import shader_root
from wgputrace.kernels.material_dispatch import material_dispatch, material_kind_constants
from wgputrace.kernels.variant import shaded_kinds
from wgputrace.reference.mitsuba_scene import bsdf_dict, emitter_dict
from wgputrace.render.lights import emitted_radiance, emitting
from wgputrace.render.scene_records import material_records
from wgputrace.scene import Diffuse, Emitter, Glass, Glossy, Material, material_class, material_classes
from wgputrace.scene.materials.principled import Principled

# A kind id no material module uses.
FREE_KIND = 250


def test_trac0r_numbering_and_wgsl_names():
    assert [(cls.kind, cls.__name__) for cls in material_classes()] == [
        (1, "Emitter"),
        (2, "Diffuse"),
        (3, "Glass"),
        (4, "Glossy"),
        (5, "Principled"),
    ]
    assert material_kind_constants() == [
        "const MATERIAL_EMITTER: u32 = 1u;",
        "const MATERIAL_DIFFUSE: u32 = 2u;",
        "const MATERIAL_GLASS: u32 = 3u;",
        "const MATERIAL_GLOSSY: u32 = 4u;",
        "const MATERIAL_PRINCIPLED: u32 = 5u;",
    ]


def test_every_kind_is_exported_where_the_old_names_were():
    for cls in material_classes():
        assert getattr(wgputrace, cls.__name__) is cls and cls.__name__ in wgputrace.__all__
        assert getattr(wgputrace.scene, cls.__name__) is cls and cls.__name__ in wgputrace.scene.__all__


def test_a_taken_kind_is_refused_by_name():
    with pytest.raises(TypeError, match=r"material kind 3 is already wgputrace\.scene\.materials\.glass\.Glass's"):

        @dataclass(eq=False)
        class Obsidian(Material):
            kind = 3

    assert material_class(3) is Glass


def test_a_taken_wgsl_name_is_refused():
    with pytest.raises(TypeError, match="MATERIAL_DIFFUSE is already kind 2"):

        class Diffuse(Material):  # noqa: F811 (the clash is the point)
            kind = FREE_KIND

    with pytest.raises(ValueError, match=f"no material kind {FREE_KIND} is registered"):
        material_class(FREE_KIND)


@pytest.mark.parametrize("kind", [0, -1, 2**32, 2.0, True])
def test_a_kind_outside_u32_ids_is_refused(kind):
    with pytest.raises(TypeError, match="kind must be an int"):
        type("Odd", (Material,), {"kind": kind})


def test_an_emission_needs_the_hosts_reading_of_it():
    with pytest.raises(TypeError, match="declares an emission but no record_radiance"):
        type("Glow", (Material,), {"kind": FREE_KIND, "emission_wgsl": "material.color"})


def test_variants_of_a_kind_share_its_code():
    class Lambert(Diffuse):
        pass

    assert Lambert.kind == Diffuse.kind and material_class(Diffuse.kind) is Diffuse


def test_dispatch_covers_only_the_kinds_asked_for():
    code = material_dispatch({Diffuse.kind, Emitter.kind})
    assert '"materials/diffuse.wgsl"' in code and "glass" not in code and "glossy" not in code
    assert "case MATERIAL_EMITTER: { return material.color; }" in code
    assert shaded_kinds([Glossy.kind, Emitter.kind, Glossy.kind]) == (1, 4)
    with pytest.raises(ValueError, match="no material kind 9"):
        shaded_kinds([9])


def test_integrator_flags_come_from_the_classes():
    code = material_dispatch()
    # a delta lobe never meets a light sample; glossy decides by roughness; an emitter has no BSDF
    assert (Glass.light_sampling(), Diffuse.light_sampling()) == ("false", "true")
    assert f"case MATERIAL_GLOSSY: {{ return {Glossy.samples_lights}; }}" in code
    two_sided = "MATERIAL_DIFFUSE, MATERIAL_GLOSSY"  # not glass; principled unless it transmits
    reflecting = "MATERIAL_DIFFUSE, MATERIAL_GLASS, MATERIAL_GLOSSY, MATERIAL_PRINCIPLED"
    assert f"case {two_sided}: {{ return true; }}" in code
    assert f"case MATERIAL_PRINCIPLED: {{ return {Principled.two_sided_wgsl}; }}" in code
    assert f"case {reflecting}: {{ return true; }}" in code


def test_records_and_light_radiance_agree():
    materials = [Diffuse("d", color=(0.1, 0.2, 0.3)), Emitter("e", color=(1.0, 0.5, 0.25), emittance=4.0)]
    records = material_records(materials)
    assert list(records["kind"]) == [Diffuse.kind, Emitter.kind]
    assert list(emitting(records)) == [False, True]
    np.testing.assert_array_equal(emitted_radiance(records), [[0, 0, 0], [4, 2, 1]])


def test_mitsuba_mapping_follows_the_flags():
    assert bsdf_dict(Diffuse("d"))["type"] == "twosided"
    assert bsdf_dict(Glass("g"))["type"] == "dielectric"
    lamp = Emitter("lamp", color=(1, 0.5, 0.25), emittance=2)
    assert bsdf_dict(lamp)["reflectance"]["value"] == [0, 0, 0]
    assert emitter_dict(lamp) == {"type": "area", "radiance": {"type": "rgb", "value": [2.0, 1.0, 0.5]}}
    assert emitter_dict(Diffuse("d")) is None


# The new kind: a mirror that tints what it reflects. Its WGSL reflects only above the surface,
# so the back of a mirror shows the light only where the generated two-sided flip ran.
TINTED_MIRROR_PY = '''\
"""TintedMirror (made by a test): a perfect mirror tinting what it reflects, the same on both sides.

| parameter | type          | default | meaning                 |
|-----------|---------------|---------|-------------------------|
| color     | RGB in [0, 1] | 1       | reflectance per channel |
"""

from dataclasses import dataclass

from ..registry import mitsuba_rgb
from .material import Material, MaterialShader


@dataclass(eq=False)
class TintedMirror(Material):
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)

    kind = {kind}
    shader = MaterialShader(
        "materials/tinted_mirror.wgsl",
        sample="tinted_mirror_sample(material.color, wi)",
        eval="vec3<f32>(0.0)",
        pdf="0.0",
    )
    delta = True

    def checked_parameters(self):
        return {{"color": self.check_color("color", self.color, upper=1.0)}}

    def fill_record(self, record):
        record["color"] = self.color

    def mitsuba_bsdf(self):
        return {{"type": "conductor", "material": "none", "specular_reflectance": mitsuba_rgb(self.color)}}
'''
TINTED_MIRROR_WGSL = """\
// Tinted mirror (made by a test): reflection about the normal, weighted by the tint, above the surface only.
//! include "materials/bsdf_sample.wgsl"

fn tinted_mirror_sample(color: vec3<f32>, wi: vec3<f32>) -> BsdfSample {
    if wi.z <= 0.0 {
        return no_bsdf_sample();
    }
    return BsdfSample(vec3<f32>(-wi.x, -wi.y, wi.z), color, 1.0, true, 1.0);
}
"""
TINT = (0.25, 0.5, 1.0)
RADIANCE = 3.0
WIDTH, HEIGHT, SPP = 16, 12, 2
# Every sample is the same product tint x radiance, rounded once; the mean of equal samples
# may round once more.
MEAN_RTOL = 4 * float(np.finfo(np.float32).eps)
# The camera looks down -z at two mirrors at z = -1 filling the view, the left one facing it, the
# right one wound the other way; every reflected ray meets the light at z = +1, behind the camera.
RENDER = """\
import json, sys
import numpy as np
import wgputrace as wt
from wgputrace.reference.mitsuba_scene import bsdf_dict

mirror = wt.TintedMirror("mirror", color={tint})
facing = [[(-4, -4, -1), (0, -4, -1), (0, 4, -1)], [(-4, -4, -1), (0, 4, -1), (-4, 4, -1)]]
away = [[(0, -4, -1), (4, 4, -1), (4, -4, -1)], [(0, -4, -1), (0, 4, -1), (4, 4, -1)]]
lamp = [[(-20, -20, 1), (20, -20, 1), (20, 20, 1)], [(-20, -20, 1), (20, 20, 1), (-20, 20, 1)]]
light = wt.Shape("light", lamp, wt.Emitter("lamp", emittance={radiance}))
scene = wt.Scene([wt.Shape("facing", facing, mirror), wt.Shape("away", away, mirror), light])
scene.camera = wt.Camera(position=(0, 0, 0), forward=(0, 0, -1))
renderer = wt.Renderer(scene, {width}, {height}, seed=1, max_depth=2)
renderer.render({spp})
np.save(sys.argv[1], renderer.image())
print(json.dumps({{
    "module": wt.__file__,
    "constant": "const MATERIAL_TINTED_MIRROR: u32 = {kind}u;" in renderer.kernel.source.text,
    "mitsuba": bsdf_dict(mirror),
}}))
"""


@pytest.mark.gpu
@pytest.mark.slow
def test_a_new_kind_is_one_python_file_and_one_wgsl_file(tmp_path):
    # a checkout of the package and its shaders with the two new files and nothing else changed
    ignore = shutil.ignore_patterns("__pycache__")
    package = Path(wgputrace.__file__).parent
    shutil.copytree(package, tmp_path / "wgputrace", ignore=ignore)
    shutil.copytree(shader_root(), tmp_path / "shaders", ignore=ignore)
    (tmp_path / "wgputrace" / "scene" / "materials" / "tinted_mirror.py").write_text(
        TINTED_MIRROR_PY.format(kind=FREE_KIND)
    )
    (tmp_path / "shaders" / "materials" / "tinted_mirror.wgsl").write_text(TINTED_MIRROR_WGSL)
    image_file = tmp_path / "image.npy"
    script = RENDER.format(tint=TINT, radiance=RADIANCE, width=WIDTH, height=HEIGHT, spp=SPP, kind=FREE_KIND)
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script), str(image_file)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.splitlines()[-1])
    assert Path(report["module"]).is_relative_to(tmp_path), "the copy must be the package imported"
    assert report["constant"]
    assert report["mitsuba"] == {
        "type": "twosided",
        "bsdf": {"type": "conductor", "material": "none", "specular_reflectance": {"type": "rgb", "value": list(TINT)}},
    }
    image = np.load(image_file)
    expected = np.float32(TINT) * np.float32(RADIANCE)
    # left half: the mirror's own sample; right half: the same after the two-sided flip. Both in
    # full: a delta lobe takes no light samples, so no MIS weight splits the light's emission.
    np.testing.assert_allclose(image, np.broadcast_to(expected, image.shape), rtol=MEAN_RTOL)


def test_every_shader_file_is_shipped():
    for cls in material_classes():
        assert cls.shader is None or (shader_root() / cls.shader.file).is_file(), cls
