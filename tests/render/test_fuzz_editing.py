"""Property-based fuzzing of the Scene editing API against a live Renderer.

Random edits (shapes added and removed, transforms, vertices, material parameters, material
reassignments, cameras), valid and not: each either takes effect or raises the documented error
(SceneError or MaterialError, both ValueErrors), leaving the scene usable. At render steps the image
is finite, the GPU buffers hold exactly the host records (no upload lost), and those equal a fresh
build's up to the BVH's order: the incremental path never drifts from the full one. A smooth,
vertex-coloured sphere among the shapes keeps the per-vertex attributes (`shared_vertices`) in it:
each triangle's corners read what a fresh build gives them. (The scene
editing tests assert bit-equal images after edits on scenes without exact hit ties; random geometry
here can stack coincident triangles, whose tie order depends on the tree.)
"""

from __future__ import annotations

import warnings
from contextlib import contextmanager

import numpy as np
import pytest
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, precondition, rule

from wgputrace import Camera, Diffuse, Emitter, Glass, Renderer, Shape, default_scene, make_icosphere
from wgputrace.render.scene_mirror import VERTEX_ARRAYS, VERTEX_COLORS, VERTEX_INDICES, VERTEX_NORMALS, SceneMirror
from wgputrace.render.shared_vertices import corner_values
from wgputrace.scene import DegenerateTrianglesWarning, MaterialError, SceneError
from wgputrace.testing.fuzzing import fuzz_settings, time_limit
from wgputrace.testing.harness import read_binding

pytestmark = pytest.mark.gpu

SIZE = 8
SEED = 9
EXAMPLES = 25
STEPS = 12

coordinates = st.one_of(
    st.floats(-2.0, 2.0, allow_subnormal=False), st.sampled_from([0.0, -0.0, 1e-30, 1e30, np.nan, np.inf])
)
vertex_arrays = st.integers(0, 6).flatmap(
    lambda n: st.lists(coordinates, min_size=9 * n, max_size=9 * n).map(lambda c: np.array(c).reshape(n, 3, 3))
)
matrix_entries = st.one_of(st.floats(-3.0, 3.0, allow_subnormal=False), st.sampled_from([0.0, 1.0, np.nan, 1e300]))
matrices = st.one_of(
    st.lists(matrix_entries, min_size=16, max_size=16).map(lambda m: np.array(m).reshape(4, 4)),
    st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)).map(
        lambda t: np.array([[1, 0, 0, t[0]], [0, 1, 0, t[1]], [0, 0, 1, t[2]], [0, 0, 0, 1.0]])
    ),
)
parameter_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.lists(st.floats(-0.5, 1.5), min_size=1, max_size=4).map(tuple),
    st.sampled_from(["red", None, (0.2, 0.3, 0.4), 1.33, 0.0]),
)


@contextmanager
def documented_errors():
    """The edit may be refused, but only with the documented errors."""
    try:
        yield
    except (SceneError, MaterialError):
        pass


def gpu_rows(renderer: Renderer, binding: str, array: np.ndarray) -> np.ndarray:
    return read_binding(renderer.context, renderer.resources[binding], array.dtype, len(array))


def sorted_records(records: np.ndarray) -> np.ndarray:
    fields = [records[name].reshape(len(records), -1).view(np.uint32) for name in records.dtype.names]
    return np.unique(np.concatenate(fields, axis=1), axis=0)


def corner_rows(mirror: SceneMirror) -> np.ndarray:
    """Each triangle's record beside its corners' attributes, as sorted rows of words (the BVH's
    order aside)."""
    count = len(mirror.triangles)
    words = [mirror.triangles[name].reshape(count, -1).view(np.uint32) for name in mirror.triangles.dtype.names]
    for name in VERTEX_ARRAYS.keys() & mirror.vertices.keys():
        corners = corner_values(mirror.vertices[VERTEX_INDICES], mirror.vertices[name])
        words.append(np.ascontiguousarray(corners).reshape(count, -1).view(np.uint32))
    return np.unique(np.concatenate(words, axis=1), axis=0)


def smooth_colored_sphere() -> Shape:
    sphere = make_icosphere((0.0, 1.0, 0.0), (0.3, 0.2, 0.1), 0.3, 1, Diffuse("sphere"), "sphere", smooth=True)
    sphere.colors = np.linspace(0.0, 1.0, sphere.triangle_count * 12).reshape(-1, 3, 4)
    return sphere


def starting_scene():
    return default_scene().add(smooth_colored_sphere())


@pytest.fixture(autouse=True, scope="module")
def compiled_kernel():
    """The starting scene's kernel compiled (cached per device and variant) before the examples are
    timed: compiling the smooth, coloured variant takes seconds on a busy lavapipe."""
    Renderer(starting_scene(), SIZE, SIZE, seed=SEED).render(1)


class SceneEditing(RuleBasedStateMachine):
    def __init__(self) -> None:
        super().__init__()
        self.scene = starting_scene()
        self.materials = [*self.scene.materials, Glass("extra_glass", ior=1.2), Emitter("extra_lamp", emittance=3.0)]
        self.added: list[Shape] = []
        self.renderer = Renderer(self.scene, SIZE, SIZE, seed=SEED)

    @rule(vertices=vertex_arrays, data=st.data())
    def add_shape(self, vertices, data):
        with documented_errors():
            shape = Shape("added", vertices, data.draw(st.sampled_from(self.materials)))
            self.scene.add(shape)
            self.added.append(shape)

    @precondition(lambda self: self.added)
    @rule(data=st.data())
    def remove_shape(self, data):
        shape = data.draw(st.sampled_from(self.added))
        self.scene.remove(shape)
        self.added.remove(shape)

    @rule(matrix=matrices, data=st.data())
    def set_transform(self, matrix, data):
        with documented_errors():
            data.draw(st.sampled_from(self.scene.shapes)).transform = matrix

    @rule(vertices=vertex_arrays, data=st.data())
    def set_vertices(self, vertices, data):
        with documented_errors():
            data.draw(st.sampled_from(self.scene.shapes)).vertices = vertices

    @rule(value=parameter_values, data=st.data())
    def set_material_parameter(self, value, data):
        material = data.draw(st.sampled_from(self.materials))
        with documented_errors():
            setattr(material, data.draw(st.sampled_from(material.parameter_names())), value)

    @rule(data=st.data())
    def reassign_material(self, data):
        data.draw(st.sampled_from(self.scene.shapes)).material = data.draw(st.sampled_from(self.materials))

    @rule(position=st.lists(coordinates, min_size=3, max_size=3), forward=st.lists(coordinates, min_size=3, max_size=3))
    def set_camera(self, position, forward):
        with documented_errors():
            self.scene.camera = Camera(position, forward, (0, 1, 0), 50.0)

    @rule()
    def render_and_check(self):
        with time_limit(), warnings.catch_warnings():
            warnings.simplefilter("ignore", DegenerateTrianglesWarning)
            try:
                self.renderer.render(1)
            except SceneError:  # every triangle removed or zero-area: documented, and nothing to check
                return
            image = self.renderer.image()
            assert np.all(np.isfinite(image))
            mirror = self.renderer._mirror
            for binding, array in (
                ("triangles", mirror.triangles),
                ("nodes", mirror.nodes),
                ("materials", mirror.materials),
                ("lights", mirror.lights.entries),
                *(
                    (binding, mirror.vertices[name])
                    for name, binding in (
                        (VERTEX_INDICES, "triangle_vertices"),
                        (VERTEX_NORMALS, "vertex_normals"),
                        (VERTEX_COLORS, "vertex_colors"),
                    )
                    if name in mirror.vertices
                ),
            ):
                np.testing.assert_array_equal(gpu_rows(self.renderer, binding, array), array)
            fresh = SceneMirror(self.scene, "bvh")
        np.testing.assert_array_equal(sorted_records(mirror.triangles), sorted_records(fresh.triangles))
        assert mirror.vertices.keys() == fresh.vertices.keys()
        np.testing.assert_array_equal(corner_rows(mirror), corner_rows(fresh))
        np.testing.assert_array_equal(mirror.materials, fresh.materials)
        # lights compared by the triangle they name: its BVH position differs between the two trees
        np.testing.assert_array_equal(
            mirror.triangles[mirror.lights.entries["triangle"]], fresh.triangles[fresh.lights.entries["triangle"]]
        )
        np.testing.assert_array_equal(mirror.lights.entries["threshold"], fresh.lights.entries["threshold"])
        np.testing.assert_array_equal(mirror.lights.entries["alias_index"], fresh.lights.entries["alias_index"])


SceneEditing.TestCase.settings = fuzz_settings(EXAMPLES, stateful_step_count=STEPS)
test_scene_editing_fuzz = SceneEditing.TestCase
