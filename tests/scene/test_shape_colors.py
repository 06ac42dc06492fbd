"""Shape.colors: linear RGBA per corner in [0, 1], checked on assignment (SceneError naming the shape
and triangle), following the corners a mirroring transform swaps; the mirror keeps them in BVH
order, white for shapes without, and only while some shape has them."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace.render.scene_mirror import VERTEX_COLORS, VERTEX_INDICES, SceneMirror
from wgputrace.render.shared_vertices import corner_values
from wgputrace.scene import Diffuse, SceneError, Shape, make_box
from wgputrace.testing.scenes import inside_emitter

MATERIAL = Diffuse("white", color=(1, 1, 1))
MIRROR = np.diag([-1.0, 1.0, 1.0, 1.0])


def colored_box(seed: int = 5) -> Shape:
    box = make_box((0, 0, 0), (0.2, 0.3, 0.1), (1, 1, 1), MATERIAL, "box")
    box.colors = np.random.default_rng(seed).random((box.triangle_count, 3, 4))
    return box


def test_colours_are_kept_read_only_as_float32():
    box = colored_box()
    assert box.colors.dtype == np.float32 and box.colors.shape == (12, 3, 4) and not box.colors.flags.writeable
    assert box.world_colors is box.colors


@pytest.mark.parametrize(
    "value, message",
    [
        (1.5, r"triangle 3 has a vertex colour that is not a number in \[0, 1\]"),
        (-0.1, "triangle 3"),
        (np.nan, "triangle 3"),
    ],
)
def test_colours_outside_the_unit_interval_are_refused_naming_shape_and_triangle(value, message):
    box = colored_box()
    colors = box.colors.copy()
    colors[3, 1, 2] = value
    before = box.geometry_version
    with pytest.raises(SceneError, match=f"shape 'box': {message}"):
        box.colors = colors
    assert box.geometry_version == before


def test_colours_of_another_triangle_count_are_refused():
    box = colored_box()
    with pytest.raises(SceneError, match=r"colors must have shape \(12, 3, 4\)"):
        box.colors = np.ones((11, 3, 4))
    with pytest.raises(SceneError, match="12 triangles of vertices but .* colors"):
        Shape("two", box.vertices[:2], MATERIAL, colors=box.colors[:2]).vertices = box.vertices


def test_a_mirroring_transform_swaps_the_colours_with_the_corners():
    box = colored_box()
    box.transform = MIRROR
    np.testing.assert_array_equal(box.world_colors, box.colors[:, [0, 2, 1]])
    baked = colored_box().transformed(MIRROR)
    np.testing.assert_array_equal(baked.colors, box.world_colors)


def test_the_mirror_keeps_colours_in_bvh_order_white_for_shapes_without():
    plain = make_box((2, 0, 0), (0, 0, 0), (1, 1, 1), MATERIAL, "plain")
    box = colored_box()
    scene = inside_emitter(plain)
    mirror = SceneMirror(scene, "bvh")
    assert VERTEX_COLORS not in mirror.vertices and not mirror.features.vertex_colors
    scene.add(box)
    changes = mirror.update()
    assert mirror.features.vertex_colors and len(changes[VERTEX_INDICES]) == len(mirror.triangles)
    # each triangle's colours, found by its corners: the box's own, white for the others
    stored = corner_values(mirror.vertices[VERTEX_INDICES], mirror.vertices[VERTEX_COLORS])
    corners = np.stack([mirror.triangles[f"v{k}"] for k in range(3)], axis=1)
    rows = [int(np.flatnonzero((corners == triangle).all(axis=(1, 2)))[0]) for triangle in box.world_vertices]
    np.testing.assert_array_equal(stored[rows], box.colors)
    assert (np.delete(stored, rows, axis=0) == 1.0).all()
    # a mirroring move (a refit) reorders the box's corners and their colours with them
    box.transform = MIRROR
    changes = mirror.update()
    assert mirror.refits == 1 and VERTEX_COLORS in changes
    stored = corner_values(mirror.vertices[VERTEX_INDICES], mirror.vertices[VERTEX_COLORS])
    np.testing.assert_array_equal(stored[rows], box.world_colors)
    box.colors = None
    mirror.update()
    assert VERTEX_COLORS not in mirror.vertices and not mirror.features.vertex_colors
