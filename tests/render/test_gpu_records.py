"""The one table of record arrays (RECORD_ARRAYS) against the declarations it serves: every binding
of the scene, lights and shading groups that holds records (and the G-buffer's object motions) has
exactly one entry, and every entry names an array the SceneMirror (or ObjectMotion) keeps and a
binding some group declares."""

from __future__ import annotations

from wgputrace import default_scene
from wgputrace.gpu.bindings import BindGroup
from wgputrace.kernels.bind_groups import OBJECT_MOTIONS, TRIANGLE_OBJECTS, lights_group, scene_group, shading_group
from wgputrace.kernels.light_dispatch import LightFeatures
from wgputrace.render.gpu_records import RECORD_ARRAYS
from wgputrace.render.object_motion import ObjectMotion
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.scene import PointLight
from wgputrace.scene.lights.environment import ENVIRONMENT_MAP

# the one binding of those groups that is the renderer's own, not a record array of the scene
RENDERER_BINDINGS = {("scene", "frame")}
EVERY_GROUP = (
    scene_group("bvh"),
    scene_group("flat"),
    scene_group("bvh", instanced=True),
    lights_group(LightFeatures((PointLight.kind,), ENVIRONMENT_MAP)),
    shading_group(smooth=True, textured=True, vertex_colors=True),
    # of the pixels group, only the G-buffer variant's object motions are the scene's records
    BindGroup("pixels", 1, (TRIANGLE_OBJECTS, OBJECT_MOTIONS)),
)


def test_every_record_binding_has_one_entry_and_every_entry_a_binding():
    declared = {(group.name, binding.name) for group in EVERY_GROUP for binding in group.bindings}
    entries = [(array.group, array.binding) for array in RECORD_ARRAYS]
    assert len(entries) == len(set(entries)), "a binding is served twice"
    assert set(entries) == declared - RENDERER_BINDINGS


def test_every_entry_is_an_array_of_the_mirror():
    scene = default_scene()
    mirror, motion = SceneMirror(scene, "bvh"), ObjectMotion()
    motion.update(scene, mirror)
    arrays = mirror.arrays | motion.arrays
    names = [array.name for array in RECORD_ARRAYS]
    assert len(names) == len(set(names))
    assert set(names) == set(arrays)
